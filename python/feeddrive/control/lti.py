"""Any linear digital controller from (x_ref, x_meas) to u, with the output clamp and an
optional back-calculation anti-windup.

The controller is the discrete state-space system (inputs ``e = [x_ref, x_meas]``)::

    v  = C s + D e                      unclamped output (+ u_ff, an added excitation)
    u  = clamp(v + u_ff, -u_limit, u_limit)
    s <- A s + B e + L (u - v - u_ff)

``L`` is the back-calculation gain (zero: no anti-windup).  The correction ``u - v - u_ff``
is exactly 0.0 while the output is inside the clamp, so the controller is then the linear
system itself, whatever ``L``.  While clamped, the state obeys
``s <- (A - L C) s + (B - L D) e + L (u - u_ff)``: the state is driven by the output that was
applied, and ``A - L C`` (which :func:`back_calculation_gain` makes Schur stable, all
eigenvalues at one chosen ``pole``) sets how fast it forgets the part the clamp cut off.
This is the observer form of back-calculation (Astrom & Hagglund, *Advanced PID Control*,
2006, on windup): for a PID realised with its integral as a state and L on that state alone it
is the classic back-calculation of the integrator (L = Ts/T_t), and, unlike
freezing the state update while clamped, it works for any structure -- a frozen state would
also stop the derivative filter, a lead or a velocity filter, whose states must follow the
measurement to be right when the clamp releases.

The state starts, at the first sample, at ``s0 + s0_r x_ref[0]``: :func:`rest_state` gives
the state the controller holds at rest with both inputs at x_ref[0] (least squares where it
integrates), so that a filter of the absolute position (a velocity filter) does not start
with a jump.

Transfer functions in z (``num``/``den`` coefficient lists in descending powers of z, as
:mod:`scipy.signal`; with equal lengths these are also ascending powers of z^-1) become a
state-space realisation with :func:`tf_to_ss`.  :func:`pid_tf` and :func:`cascade_tf` build
the PID with filtered derivative and lead, and the cascaded P-PI with a velocity filter.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import cast

import numpy as np
from numpy.typing import ArrayLike
from scipy import linalg, signal

from .pid import lead_coefficients

#: The most states the controller FMU holds (and so the registry accepts).
LTI_MAX_ORDER = 8

StepFunction = Callable[[list[float], float, float, float], float]


def _poly(c: ArrayLike, what: str) -> np.ndarray:
    p = np.atleast_1d(np.asarray(c, dtype=float))
    if p.ndim != 1 or p.size == 0 or not np.all(np.isfinite(p)):
        raise ValueError(f"lti: {what} must be a non-empty list of finite numbers")
    return p


def _aligned(p: np.ndarray, m: int, what: str) -> np.ndarray:
    """``p`` (descending powers of z) as ``m`` coefficients; ValueError when of higher degree."""
    p = np.trim_zeros(p, "f")
    if p.size > m:
        raise ValueError(
            f"lti: {what} has degree {p.size - 1} > the denominator's {m - 1} (not causal)"
        )
    return np.concatenate([np.zeros(m - p.size), p])


def _add(*polys: np.ndarray) -> np.ndarray:
    """Sum of polynomials in z^-1 (coefficients from z^0 up: aligned at the front)."""
    m = max(len(p) for p in polys)
    out = np.zeros(m)
    for p in polys:
        out += np.pad(np.asarray(p, float), (0, m - len(p)))
    return out


def tf_to_ss(
    num: Sequence[ArrayLike], den: ArrayLike | Sequence[ArrayLike]
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(A, B, C, D) of u = N_r(z)/D_r(z) x_ref + N_y(z)/D_y(z) x_meas.

    Parameters
    ----------
    num : ``[num_r, num_y]``, coefficients in descending powers of z.
    den : one common denominator, or ``[den_r, den_y]`` (then brought over the common
        denominator D_r D_y).

    The realisation is the observable canonical form of the two-input system (always
    observable, so :func:`back_calculation_gain` applies); its order is the degree of the
    common denominator.  A (n, n), B (n, 2), C (1, n), D (1, 2).
    """
    if len(num) != 2:
        raise ValueError(f"lti: num must be [num for x_ref, num for x_meas], got {len(num)} lists")
    nr, ny = _poly(num[0], "num[0]"), _poly(num[1], "num[1]")
    dens = cast(Sequence[ArrayLike], den)  # one list of numbers, or two lists
    if len(dens) and np.ndim(dens[0]) > 0:
        if len(dens) != 2:
            raise ValueError(
                f"lti: den must be one list or [den for x_ref, den for x_meas], "
                f"got {len(dens)} lists"
            )
        dr = np.trim_zeros(_poly(dens[0], "den[0]"), "f")
        dy = np.trim_zeros(_poly(dens[1], "den[1]"), "f")
        if dr.size == 0 or dy.size == 0:
            raise ValueError("lti: a denominator is zero")
        nr = np.polymul(_aligned(nr, dr.size, "num[0]"), dy)
        ny = np.polymul(_aligned(ny, dy.size, "num[1]"), dr)
        d = np.polymul(dr, dy)
    else:
        d = np.trim_zeros(_poly(cast(ArrayLike, den), "den"), "f")
        if d.size == 0:
            raise ValueError("lti: den is zero")
    nums = np.vstack([_aligned(p, d.size, w) for p, w in ((nr, "num[0]"), (ny, "num[1]"))])
    if d.size == 1:
        return (
            np.zeros((0, 0)),
            np.zeros((0, 2)),
            np.zeros((1, 0)),
            (nums[:, 0] / d[0]).reshape(1, 2),
        )
    At, Bt, Ct, Dt = signal.tf2ss(nums, d)  # one input, two outputs: transpose
    return At.T.copy(), Ct.T.copy(), Bt.T.copy(), Dt.T.copy()


def back_calculation_gain(A: ArrayLike, C: ArrayLike, pole: float = 0.0) -> np.ndarray:
    """L (n,) that puts every eigenvalue of ``A - L C`` at ``pole`` (Ackermann's formula).

    ``pole`` in [0, 1): 0 is deadbeat (the state agrees with the applied output after n
    samples of clamping), closer to 1 slower.  ValueError when (A, C) is not observable (a
    realisation with a state the output never sees).
    """
    A = np.atleast_2d(np.asarray(A, dtype=float))
    C = np.asarray(C, dtype=float).reshape(1, -1)
    n = A.shape[0]
    if not 0.0 <= pole < 1.0:
        raise ValueError(f"lti: anti-windup pole = {pole!r}: allowed [0, 1)")
    O = np.vstack([C @ np.linalg.matrix_power(A, k) for k in range(n)])
    if np.linalg.matrix_rank(O) < n:
        raise ValueError(
            "lti: anti-windup: (A, C) is not observable; give the gain L "
            "explicitly or a minimal realisation"
        )
    phi = np.linalg.matrix_power(A - pole * np.eye(n), n)
    e = np.zeros(n)
    e[-1] = 1.0
    return phi @ np.linalg.solve(O, e)


def rest_state(A: ArrayLike, B: ArrayLike, C: ArrayLike, D: ArrayLike) -> np.ndarray:
    """s0_r: the state at rest with both inputs at x is s0_r x.

    A solution of (I - A) s = (B[:, 0] + B[:, 1]) x (least squares, minimum norm); where the
    controller integrates (I - A singular), the free part is chosen so that the output at
    rest, C s + (D[0] + D[1]) x, is 0 where it can be: an integrator starts empty."""
    A = np.atleast_2d(np.asarray(A, dtype=float))
    n = A.shape[0] if A.size else 0
    if n == 0:
        return np.zeros(0)
    A = A.reshape(n, n)
    B = np.asarray(B, dtype=float).reshape(n, 2)
    C = np.asarray(C, dtype=float).reshape(1, n)
    D = np.asarray(D, dtype=float).reshape(1, 2)
    M = np.eye(n) - A
    s = np.linalg.pinv(M) @ (B[:, 0] + B[:, 1])
    N = linalg.null_space(M, rcond=1e-12)
    if N.size:
        c = np.linalg.lstsq(C @ N, -(C @ s + D.sum()), rcond=None)[0]
        s = s + N @ c
    return s


def _sum(terms: list[tuple[float, str]]) -> str:
    return " + ".join(["0.0"] + [f"{float(c)!r}*{v}" for c, v in terms])


def compile_lti_step(
    A: np.ndarray, B: np.ndarray, C: np.ndarray, D: np.ndarray, L: np.ndarray, u_limit: float
) -> StepFunction:
    """``step(s, r, y, u_ff) -> u`` updating the state list ``s`` in place, with the
    operations of the controller FMU in the same order (every term, left to right)."""
    n = A.shape[0]
    names = [f"s{j}" for j in range(n)]
    lines = ["def step(s, r, y, uff):"]
    if n:
        lines.append(f"    {', '.join(names)}{',' if n == 1 else ''} = s")
    lines.append(
        "    v = "
        + _sum([(C[0, j], names[j]) for j in range(n)] + [(D[0, 0], "r"), (D[0, 1], "y")])
    )
    lim = float(u_limit)
    lines += [
        "    w = v + uff",
        f"    u = {lim!r} if w > {lim!r} else ({-lim!r} if w < {-lim!r} else w)",
        "    c = u - w",
    ]
    for i in range(n):
        lines.append(
            f"    s[{i}] = "
            + _sum(
                [(A[i, j], names[j]) for j in range(n)]
                + [(B[i, 0], "r"), (B[i, 1], "y"), (L[i], "c")]
            )
        )
    lines.append("    return u")
    src = "\n".join(lines)
    namespace: dict[str, object] = {}
    exec(compile(src, "<feeddrive.control.lti>", "exec"), namespace)
    return namespace["step"]  # type: ignore[return-value]


class LTIController:
    """The general linear controller (module docstring), ``reset()`` / ``step(x_meas, k)``.

    Parameters
    ----------
    reference : x_ref[k] [m] sampled at Ts (held at its last value beyond the end).
    A, B, C, D : (n, n), (n, 2), (1, n), (1, 2); inputs (x_ref, x_meas) [m], output [V].
    u_limit : output clamp +- [V].
    L : back-calculation gain (n,), or None (no anti-windup).
    s0, s0_r : the first state is s0 + s0_r x_ref[0] (None: zeros).
    u_ff : voltage added to the output per sample (zero beyond its end), or None.
    """

    def __init__(
        self,
        reference: ArrayLike,
        A: ArrayLike,
        B: ArrayLike,
        C: ArrayLike,
        D: ArrayLike,
        u_limit: float,
        L: ArrayLike | None = None,
        s0: ArrayLike | None = None,
        s0_r: ArrayLike | None = None,
        u_ff: ArrayLike | None = None,
    ) -> None:
        self.A = np.atleast_2d(np.asarray(A, dtype=float))
        n = self.A.shape[0] if self.A.size else 0
        self.A = self.A.reshape(n, n)
        self.B = np.asarray(B, dtype=float).reshape(n, 2)
        self.C = np.asarray(C, dtype=float).reshape(1, n)
        self.D = np.asarray(D, dtype=float).reshape(1, 2)
        vec = [
            np.zeros(n) if v is None else np.asarray(v, dtype=float).reshape(n)
            for v in (L, s0, s0_r)
        ]
        self.L, self.s0, self.s0_r = vec
        if not (u_limit > 0 and np.isfinite(u_limit)):
            raise ValueError(f"lti: u_limit = {u_limit!r} must be a finite number > 0 [V]")
        for name in ("A", "B", "C", "D", "L", "s0", "s0_r"):
            if not np.all(np.isfinite(getattr(self, name))):
                raise ValueError(f"lti: {name} has a value that is not finite")
        self.u_limit = float(u_limit)
        self.x_ref = np.asarray(reference, dtype=float).copy()
        if self.x_ref.ndim != 1 or self.x_ref.size == 0:
            raise ValueError("lti: reference must be a non-empty 1-D array")
        self._r = self.x_ref.tolist()
        self._uff = [] if u_ff is None else np.asarray(u_ff, dtype=float).tolist()
        self._step = compile_lti_step(self.A, self.B, self.C, self.D, self.L, self.u_limit)
        self.reset()

    @property
    def n(self) -> int:
        """Order (number of states)."""
        return self.A.shape[0]

    def reset(self) -> None:
        """Back to before the first sample (the state is set from the first inputs)."""
        self._s: list[float] = []

    def step(self, x_meas: float, k: int) -> float:
        """Controller output [V] at sample k from the measured position [m]."""
        r = self._r[k] if k < len(self._r) else self._r[-1]
        y = float(x_meas)
        if not self._s and self.n:
            self._s = (self.s0 + self.s0_r * r).tolist()
        uff = self._uff[k] if k < len(self._uff) else 0.0
        return self._step(self._s, r, y, uff)


def pid_tf(
    Kp: float,
    Kv: float,
    Ki: float,
    force_per_volt: float,
    Ts: float,
    tf: float = 0.0,
    lead: tuple[float, float] | None = None,
) -> tuple[list[list[float]], list[float]]:
    """``(num, den)`` of the force-equivalent PID of :class:`~feeddrive.control.pid.PID`
    (gains Kp [N/m], Kv [N s/m], Ki [N/(m s)]; derivative filter ``tf`` [s]; lead
    (zero_hz, pole_hz) on the force command, Tustin) as transfer functions in z on the error
    e = x_ref - x_meas: ``num = [N, -N]``.

    Integrator Ts/(1 - z^-1) (backward Euler, the current error included), derivative
    Kv (1 - z^-1)/(tf + Ts - tf z^-1) (backward difference through the filter)."""
    z1 = np.array([1.0, -1.0])  # 1 - z^-1 (times z: descending powers)
    a = tf / (tf + Ts)
    dD = np.array([1.0, -a])  # 1 - a z^-1
    # F/e = Kp + Ki Ts/(1 - z^-1) + Kv/(tf + Ts) (1 - z^-1)/(1 - a z^-1), over the common
    # denominator (1 - z^-1)(1 - a z^-1)
    num = _add(Kp * np.polymul(z1, dD), Ki * Ts * dD, Kv / (tf + Ts) * np.polymul(z1, z1))
    den = _add(np.polymul(z1, dD), np.zeros(len(num)))
    if lead is not None:
        lb, la = lead_coefficients(lead[0], lead[1], Ts)
        num, den = np.polymul(num, lb), np.polymul(den, la)
    num = _add(num, np.zeros(len(den))) / force_per_volt
    den = _add(den, np.zeros(len(num)))
    return [num.tolist(), (-num).tolist()], den.tolist()


def cascade_tf(
    Kx: float, Kv: float, Ti: float, f_velocity: float, Ts: float
) -> tuple[list[list[float]], list[float]]:
    """``(num, den)`` of the cascaded P-PI position controller with a velocity filter:

        v_ref = Kx (x_ref - x_meas)                          position P [1/s]
        v     = (1 - z^-1)/Ts * (1 - a)/(1 - a z^-1) x_meas  velocity, first-order low-pass
                                                             at f_velocity [Hz], a = e^(-2 pi f Ts)
        u     = Kv (1 + Ts/(Ti (1 - z^-1))) (v_ref - v)      velocity PI [V s/m], Ti [s]

    over the common denominator (1 - z^-1)(1 - a z^-1) (order 2)."""
    a = float(np.exp(-2 * np.pi * f_velocity * Ts))
    pi_num = Kv * np.array([1.0 + Ts / Ti, -1.0])  # Kv (1 + Ts/Ti - z^-1)
    vel_num = (1.0 - a) / Ts * np.array([1.0, -1.0])
    vel_den = np.array([1.0, -a])
    num_r = Kx * np.polymul(pi_num, vel_den)
    num_y = -np.polymul(pi_num, Kx * vel_den + vel_num)
    return [num_r.tolist(), num_y.tolist()], np.polymul([1.0, -1.0], vel_den).tolist()
