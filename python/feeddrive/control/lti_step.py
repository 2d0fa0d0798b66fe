"""A sampled linear controller as a fast per-sample Python function.

The controller is

    u_fb = Cc s + Dy y + Dr r
    u    = clip(u_fb + u_ff, u_min, u_max)
    s   <- Ac s + By y + Br r + Bu (u - u_ff)

with y the measurement, r the reference, u_ff the feedforward of that sample.  The state
update sees the applied voltage less the feedforward (the part of the input that the design
model is meant to describe; a feedforward cancels forces the design model does not have).

For speed (a controller step must cost about a microsecond, MODEL-harness budget), the
matrices are unrolled into straight-line Python source with the coefficients as float
literals (exact ``repr`` round trip) and compiled once; zero coefficients are skipped.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

StepFunction = Callable[[list[float], float, float, float], float]


def _affine(terms: list[tuple[float, str]]) -> str:
    parts = [f"{float(c)!r}*{name}" for c, name in terms if c != 0.0]
    return " + ".join(parts) if parts else "0.0"


def compile_step(
    Ac: np.ndarray,
    By: np.ndarray,
    Br: np.ndarray,
    Bu: np.ndarray,
    Cc: np.ndarray,
    Dy: float,
    Dr: float,
    u_min: float = -np.inf,
    u_max: float = np.inf,
) -> StepFunction:
    """Return ``step(s, y, r, u_ff) -> u`` that updates the state list ``s`` in place.

    Parameters
    ----------
    Ac : (n, n) state matrix; By, Br, Bu : (n,) input vectors for y, r and u - u_ff.
    Cc : (n,) output row; Dy, Dr : feedthroughs of y and r.
    u_min, u_max : output limits [V].
    """
    Ac = np.atleast_2d(np.asarray(Ac, dtype=float))
    n = Ac.shape[0]
    By, Br, Bu, Cc = (np.asarray(v, dtype=float).reshape(n) for v in (By, Br, Bu, Cc))
    if not (u_min < u_max):
        raise ValueError(f"lti_step.py: need u_min < u_max (got {u_min}, {u_max})")
    names = [f"s{j}" for j in range(n)]
    lines = ["def step(s, y, r, uff):"]
    if n:
        lines.append(f"    {', '.join(names)}{',' if n == 1 else ''} = s")
    lines.append(
        "    u = "
        + _affine([(Cc[j], names[j]) for j in range(n)] + [(float(Dy), "y"), (float(Dr), "r")])
        + " + uff"
    )
    if np.isfinite(u_max):
        lines.append(f"    if u > {float(u_max)!r}: u = {float(u_max)!r}")
    if np.isfinite(u_min):
        lines.append(f"    if u < {float(u_min)!r}: u = {float(u_min)!r}")
    lines.append("    w = u - uff")
    for i in range(n):
        lines.append(
            f"    s[{i}] = "
            + _affine(
                [(Ac[i, j], names[j]) for j in range(n)]
                + [(By[i], "y"), (Br[i], "r"), (Bu[i], "w")]
            )
        )
    lines.append("    return u")
    src = "\n".join(lines)
    namespace: dict[str, object] = {}
    exec(compile(src, "<feeddrive.control.lti_step>", "exec"), namespace)
    fn = namespace["step"]
    fn.__doc__ = "Generated controller step:\n" + src
    return fn  # type: ignore[return-value]
