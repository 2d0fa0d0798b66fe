"""Signal helpers shared by the identification modules (private).

Everything here works on plain arrays or on :class:`feeddrive.data.Run` objects and is in SI.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Union

import numpy as np
from scipy.signal import savgol_filter

from .. import maps
from ..data import Run

#: A position map given either as FMU parameters (evaluated with feeddrive.maps) or a callable.
MapSpec = Union[Mapping[str, float], Callable[[np.ndarray], np.ndarray]]

#: Quantisation step of the paper's linear scale [m].
SCALE_RESOLUTION = 1e-7


def run_label(run: Run) -> str:
    """A short name for messages: the file path, else meta['name'], else 'run'."""
    if getattr(run, "path", None) is not None:
        return str(run.path)
    return str(getattr(run, "meta", {}).get("name", "run")) or "run"


def signal(run: Run, name: str) -> np.ndarray:
    """Column ``name`` of ``run`` as float array; ValueError naming the run if absent."""
    value = getattr(run, name, None)
    if value is None:
        raise ValueError(f"{run_label(run)}: column {name!r} is required here but absent")
    return np.asarray(value, dtype=float)


def sample_time(time: np.ndarray, rel_tol: float = 0.01, label: str = "run") -> float:
    """Median sample interval; ValueError when the sampling is not uniform within rel_tol."""
    dt = np.diff(np.asarray(time, dtype=float))
    if dt.size == 0:
        raise ValueError(f"{label}: fewer than 2 samples")
    Ts = float(np.median(dt))
    if np.max(np.abs(dt - Ts)) > rel_tol * Ts:
        raise ValueError(f"{label}: time is not uniformly sampled (Ts = {Ts:g} s, "
                         f"steps from {dt.min():g} to {dt.max():g} s)")
    return Ts


def run_load(run: Run) -> tuple[float, str]:
    """The constant external load P [N] of a run and where it came from.

    ``run.F_load`` (its mean) if present, else meta keys 'F_load', 'load' or 'P', else 0
    (DATA.md: an absent F_load column means no load).
    """
    if getattr(run, "F_load", None) is not None:
        return float(np.mean(run.F_load)), "column F_load"
    meta = getattr(run, "meta", {}) or {}
    for key in ("F_load", "load", "P"):
        if key in meta:
            try:
                return float(meta[key]), f"meta[{key!r}]"
            except (TypeError, ValueError):
                raise ValueError(f"{run_label(run)}: meta[{key!r}] = {meta[key]!r} is not a number")
    return 0.0, "absent (0)"


def odd_window(window: int, n: int | None = None) -> int:
    """``window`` made odd (and at most n, when given)."""
    w = int(window) | 1
    if n is not None and w > n:
        w = n if n % 2 else n - 1
    return max(w, 3)


def derivatives(x: np.ndarray, Ts: float, window: int, polyorder: int = 3
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Savitzky-Golay smoothed x, its first and second derivative (same window)."""
    w = odd_window(window, len(x))
    p = min(polyorder, w - 1)
    xs = savgol_filter(x, w, p)
    v = savgol_filter(x, w, p, deriv=1, delta=Ts)
    a = savgol_filter(x, w, max(p, 2), deriv=2, delta=Ts)
    return xs, v, a


def smooth(y: np.ndarray, window: int, polyorder: int = 3) -> np.ndarray:
    """Savitzky-Golay smoothing with the same window as :func:`derivatives`."""
    w = odd_window(window, len(y))
    return savgol_filter(np.asarray(y, dtype=float), w, min(polyorder, w - 1))


def eval_map(spec: MapSpec, name: str, x: np.ndarray) -> np.ndarray:
    """Evaluate K_f ('ripple') or F_cg ('cogging') at x from FMU parameters or a callable."""
    if callable(spec):
        return np.asarray(spec(np.asarray(x, dtype=float)), dtype=float)
    return maps.evaluate(name, x, spec, clamp=True)


def steady_segment(x: np.ndarray, Ts: float, window: int = 201, rel_tol: float = 0.25,
                   label: str = "run") -> tuple[slice, float]:
    """The longest stretch of constant velocity and its speed (signed, from a line fit).

    Velocity from a Savitzky-Golay derivative; the reference speed is the median over
    samples moving faster than half the 99th percentile of |v|; the segment is the longest
    contiguous run with |v - v_ref| <= rel_tol |v_ref|, shortened by half a window at each
    end (acceleration and deceleration transients are thereby dropped).
    """
    x = np.asarray(x, dtype=float)
    w = odd_window(window, len(x))
    v = savgol_filter(x, w, 2, deriv=1, delta=Ts)
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
    speed = float(np.polyfit(t, x[seg], 1)[0])
    return seg, speed


def collapse_positions(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unique (quantised) positions in increasing order and the mean of y at each."""
    xu, inv = np.unique(np.asarray(x, dtype=float), return_inverse=True)
    cnt = np.bincount(inv)
    return xu, np.bincount(inv, weights=np.asarray(y, dtype=float)) / cnt


def to_grid(x: np.ndarray, y: np.ndarray, grid: np.ndarray, method: str = "interp",
            step: float | None = None) -> np.ndarray:
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
        raise ValueError(f"{label}: the constant-speed segments share no stroke "
                         f"(common range {lo:g} .. {hi:g} m)")
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
