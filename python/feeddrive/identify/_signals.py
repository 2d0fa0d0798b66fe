"""Signal helpers shared by the identification modules (private).

Everything here works on plain arrays or on :class:`feeddrive.data.Run` objects and is in SI.
The physics (Eq. 1 on measured data, maps, friction curves) is :mod:`feeddrive.physics`'s.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..data import Run
from ..signals import odd_window, run_label


def signal(run: Run, name: str) -> np.ndarray:
    """Column ``name`` of ``run`` as float array; ValueError naming the run if absent."""
    value = getattr(run, name, None)
    if value is None:
        raise ValueError(f"{run_label(run)}: column {name!r} is required here but absent")
    return np.asarray(value, dtype=float)


def current(run: Run, dc_gain: float | None = None) -> np.ndarray:
    """Measured current ``run.i``; without it, i = dc_gain * u when dc_gain is given.

    The recording format: a run without an ``i`` column (amplifier taken as ideal) is processed with the
    current loop's static gain G(1) [A/V] on ``u``; this is announced with a warning.
    """
    if getattr(run, "i", None) is not None:
        return np.asarray(run.i, dtype=float)
    if dc_gain is None:
        raise ValueError(
            f"{run_label(run)}: column 'i' is absent; pass dc_gain (the current "
            "loop's static gain G(1) [A/V]) to use i = G(1) u"
        )
    warnings.warn(
        f"{run_label(run)}: no measured current, using i = {dc_gain:g} A/V * u "
        "(static current-loop gain, current dynamics ignored)",
        stacklevel=3,
    )
    return dc_gain * signal(run, "u")


def steady_segment(
    x: np.ndarray, Ts: float, window: int = 201, rel_tol: float = 0.25, label: str = "run"
) -> tuple[slice, float]:
    """The longest stretch of constant velocity and its speed (signed, from a line fit).

    Velocity from a central difference over ``window`` samples; the reference speed is the
    median over samples moving faster than half the 99th percentile of |v|; the segment is the
    longest contiguous run with |v - v_ref| <= rel_tol |v_ref|, shortened by half a window at
    each end (acceleration and deceleration transients are thereby dropped).
    """
    x = np.asarray(x, dtype=float)
    w = odd_window(window, len(x))
    h = w // 2
    v = np.empty_like(x)
    v[h : len(x) - h] = (x[2 * h :] - x[: len(x) - 2 * h]) / (2 * h * Ts)
    v[:h], v[len(x) - h :] = v[h], v[len(x) - h - 1]
    vmax = np.percentile(np.abs(v), 99)
    if vmax <= 0:
        raise ValueError(f"{label}: the position does not move")
    moving = np.abs(v) >= 0.5 * vmax
    v_ref = float(np.median(v[moving]))
    ok = np.abs(v - v_ref) <= rel_tol * abs(v_ref)
    # longest run of True
    edges = np.flatnonzero(np.diff(np.concatenate(([0], ok.astype(int), [0]))))
    starts, stops = edges[0::2], edges[1::2]
    j = int(np.argmax(stops - starts))
    lo, hi = starts[j] + w // 2, stops[j] - w // 2
    if hi - lo < 10:
        raise ValueError(f"{label}: no constant-speed segment found (v_ref = {v_ref:g} m/s)")
    seg = slice(int(lo), int(hi))
    t = np.arange(hi - lo) * Ts
    t = t - t.mean()
    speed = float(t @ (x[seg] - x[seg].mean()) / (t @ t))
    return seg, speed


def collapse_positions(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unique (quantised) positions in increasing order and the mean of y at each."""
    xu, inv = np.unique(np.asarray(x, dtype=float), return_inverse=True)
    cnt = np.bincount(inv)
    return xu, np.bincount(inv, weights=np.asarray(y, dtype=float)) / cnt


def to_grid(
    x: np.ndarray,
    y: np.ndarray,
    grid: np.ndarray,
    method: str = "interp",
    step: float | None = None,
) -> np.ndarray:
    """Resample y(x) of one monotonic segment onto ``grid``.

    ``interp``: linear interpolation (np.interp) after averaging y over repeated quantised
    positions (the paper's procedure).  ``bin``: mean of y over |x - g| < step/2 for each
    grid point g (falls back to interpolation for empty bins).
    """
    xu, yu = collapse_positions(x, y)
    if method == "interp":
        return np.interp(grid, xu, yu)
    if method != "bin":
        raise ValueError(f"resampling method must be 'interp' or 'bin', got {method!r}")
    if step is None:
        step = float(np.median(np.diff(grid)))
    idx = np.rint((np.asarray(x) - grid[0]) / step).astype(int)
    ok = (idx >= 0) & (idx < len(grid))
    s = np.bincount(idx[ok], weights=np.asarray(y, dtype=float)[ok], minlength=len(grid))
    c = np.bincount(idx[ok], minlength=len(grid))
    out = np.interp(grid, xu, yu)
    out[c > 0] = s[c > 0] / c[c > 0]
    return out


def common_grid(ranges: list[tuple[float, float]], step: float, label: str = "runs") -> np.ndarray:
    """Grid k*step (k integer, origin x = 0) covering the intersection of all ranges."""
    lo = max(r[0] for r in ranges)
    hi = min(r[1] for r in ranges)
    k0, k1 = int(np.ceil(lo / step - 1e-9)), int(np.floor(hi / step + 1e-9))
    if k1 - k0 < 2:
        raise ValueError(
            f"{label}: the constant-speed segments share no stroke "
            f"(common range {lo:g} .. {hi:g} m)"
        )
    return np.arange(k0, k1 + 1) * step


def lstsq_with_stderr(A: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Linear least squares: parameters, standard errors (s^2 (A'A)^-1), residual."""
    theta, *_ = np.linalg.lstsq(A, y, rcond=None)
    r = y - A @ theta
    dof = max(len(y) - A.shape[1], 1)
    s2 = float(r @ r) / dof
    cov = s2 * np.linalg.pinv(A.T @ A)
    return theta, np.sqrt(np.clip(np.diag(cov), 0.0, None)), r


def jacobian_stderr(jac: np.ndarray, resid: np.ndarray) -> np.ndarray:
    """Standard errors s^2 (J'J)^-1 of a nonlinear least-squares solution."""
    dof = max(len(resid) - jac.shape[1], 1)
    s2 = float(resid @ resid) / dof
    cov = s2 * np.linalg.pinv(jac.T @ jac)
    return np.sqrt(np.clip(np.diag(cov), 0.0, None))
