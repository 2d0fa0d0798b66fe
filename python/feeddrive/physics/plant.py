"""Eq. 1 on measured data:  m a = K_f(x) i - F_cg(x) - F_f - F_e - F_offset.

The acceleration is the Savitzky-Golay second derivative of the measured position and K the
smoothing kernel that differentiator applies to the true acceleration
(:func:`feeddrive.signals.matched_acceleration`); the force side is filtered with the same K.
The current is held over each sample interval (Eq. 2 is sampled), so the central second
difference at t_k sees the mean of the two held values around t_k (:func:`held_current`).
The external load F_e of a run comes from :func:`run_load`.  C twin: fmu_src/physics/plant.c.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.signal import savgol_coeffs, savgol_filter

from ..data import Run
from ..signals import apply_kernel, matched_acceleration, odd_window, run_label, sample_time
from .position_maps import MapSpec, eval_map

#: How a recorded current sample relates to the current acting on the stage.
CURRENT_TIMINGS = ("held", "held_previous", "sampled")
#: Savitzky-Golay polynomial order of the differentiators.
DEFAULT_POLYORDER = 3
#: Shortest Savitzky-Golay window [s] of the velocity the GMS friction is driven by (11
#: samples at 0.5 ms): the GMS sticks its elements where v changes sign, and the
#: acceleration's 20 ms smoother moves the sign change of a stop's small overshoot by
#: milliseconds, which leaves the held force wrong by up to 1 N for the rest that follows.
FRICTION_VELOCITY_S = 0.005
#: Largest rms of that velocity from the position's rounding [m/s] (q / sqrt(12) through
#: the differentiator; 5 ms gives 14 um/s at 100 nm, far below the Stribeck velocity): a
#: coarser scale gets a longer window.
FRICTION_VELOCITY_NOISE = 15e-6


def held_current(i: ArrayLike, timing: str = "held") -> np.ndarray:
    """The current (or any held force) a central second difference of x sees at sample k.

    - 'held': i[k] acts over [t_k, t_k+1) (the sampled current loop of Eq. 2):
      (i[k-1] + i[k]) / 2, i[0] kept.
    - 'held_previous': i[k] acted over [t_k-1, t_k) (recorded one sample late):
      (i[k] + i[k+1]) / 2, the last sample kept.
    - 'sampled': i is a continuous current sampled at t_k: i[k].
    """
    i = np.asarray(i, dtype=float)
    out = i.copy()
    if timing == "held":
        out[1:] = 0.5 * (i[1:] + i[:-1])
    elif timing == "held_previous":
        out[:-1] = 0.5 * (i[:-1] + i[1:])
    elif timing != "sampled":
        raise ValueError(f"current_timing must be one of {CURRENT_TIMINGS}, got {timing!r}")
    return out


def _load(run: Run) -> tuple[np.ndarray | float, str]:
    """The load column, or a constant from the sidecar, and where it came from."""
    if getattr(run, "F_load", None) is not None:
        return np.asarray(run.F_load, dtype=float), "column F_load"
    meta = getattr(run, "meta", {}) or {}
    for key in ("F_load", "load", "P"):
        if key in meta:
            try:
                return float(meta[key]), f"meta[{key!r}]"
            except (TypeError, ValueError):
                raise ValueError(
                    f"{run_label(run)}: meta[{key!r}] = {meta[key]!r} is not a number"
                ) from None
    return 0.0, "absent (0)"


def run_load(run: Run) -> tuple[np.ndarray, str]:
    """The external load F_e [N] per sample of a run and where it came from.

    Column ``F_load`` if present, else meta keys 'F_load', 'load' or 'P' (a constant), else 0
    (the recording format: an absent F_load column means no load).
    """
    F, src = _load(run)
    return (F if isinstance(F, np.ndarray) else np.full(len(run.time), F)), src


def run_load_mean(run: Run) -> tuple[float, str]:
    """The run's load as one number [N] (the column's mean) and where it came from."""
    F, src = _load(run)
    return float(np.mean(F)) if isinstance(F, np.ndarray) else F, src


def measured_motion(
    x: ArrayLike, Ts: float, window: int, polyorder: int = DEFAULT_POLYORDER
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(v, a, K) of a measured position: Savitzky-Golay velocity, acceleration (NaN within
    half a window of the ends) and the kernel K the acceleration estimate applies."""
    x = np.asarray(x, dtype=float)
    w = odd_window(window, len(x))
    p = min(polyorder, w - 1)
    v = savgol_filter(x, w, p, deriv=1, delta=Ts)
    a, K = matched_acceleration(x, Ts, w, p)
    return v, a, K


def friction_velocity(
    x: np.ndarray, Ts: float, window: int, polyorder: int = DEFAULT_POLYORDER
) -> np.ndarray:
    """The velocity the GMS friction is driven by [m/s]: Savitzky-Golay over the shortest
    window of at least ``FRICTION_VELOCITY_S`` whose rounding noise, for the position step
    of ``x`` (its smallest step between distinct values), stays below
    ``FRICTION_VELOCITY_NOISE``; never longer than ``window`` samples."""
    x = np.asarray(x, dtype=float)
    u = np.unique(np.round(x, 12))
    d = np.diff(u)
    d = d[d > 1e-12]
    q = float(d.min()) if d.size else 0.0
    top = odd_window(window, len(x))
    w = max(
        odd_window(int(round(FRICTION_VELOCITY_S / Ts)), len(x)), odd_window(polyorder + 2, len(x))
    )
    while w < top:
        p = min(polyorder, w - 1)
        c = savgol_coeffs(w, p, deriv=1, delta=Ts)
        if q / np.sqrt(12.0) * float(np.linalg.norm(c)) <= FRICTION_VELOCITY_NOISE:
            break
        w += 2
    w = min(w, top)
    return savgol_filter(x, w, min(polyorder, w - 1), deriv=1, delta=Ts)


def applied_force(
    F_motor: ArrayLike, F_cg: ArrayLike, F_load: ArrayLike = 0.0, F_offset: float = 0.0
) -> np.ndarray:
    """The force on the stage without friction, F_motor - F_cg - F_e - F_offset [N]."""
    return (
        np.asarray(F_motor, dtype=float)
        - np.asarray(F_cg, dtype=float)
        - np.asarray(F_load, dtype=float)
        - F_offset
    )


def eq1_terms(
    time: ArrayLike,
    x: ArrayLike,
    i: ArrayLike,
    force_constant: MapSpec,
    cogging: MapSpec,
    F_load: ArrayLike = 0.0,
    window: int = 41,
    current_timing: str = "held",
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
    """The known terms of Eq. 1 along a run: (force, a, v, K, Ts) with
    force = K_f(x) i - F_cg(x) - F_e (unfiltered), a and K from :func:`measured_motion`, the
    current taken as :func:`held_current` with ``current_timing``."""
    t = np.asarray(time, dtype=float)
    x, i = np.asarray(x, dtype=float), np.asarray(i, dtype=float)
    Ts = sample_time(t)
    v, a, K = measured_motion(x, Ts, window)
    force = applied_force(
        eval_map(force_constant, "ripple", x) * held_current(i, current_timing),
        eval_map(cogging, "cogging", x),
        np.broadcast_to(np.asarray(F_load, dtype=float), x.shape),
    )
    return force, a, v, K, Ts


def eq1_friction(
    time: ArrayLike,
    x: ArrayLike,
    i: ArrayLike,
    m: float,
    force_constant: MapSpec,
    cogging: MapSpec,
    F_load: ArrayLike = 0.0,
    window: int = 41,
    current_timing: str = "held",
) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Friction from Eq. 1, F_f = K (K_f(x) i - F_cg(x) - F_e) - m a (:func:`eq1_terms`).
    Returns (F_f, v, K, Ts); F_f is NaN within half a window of the ends."""
    force, a, v, K, Ts = eq1_terms(
        time, x, i, force_constant, cogging, F_load, window, current_timing
    )
    return apply_kernel(force, K) - m * a, v, K, Ts


def force_residual(
    F_app: ArrayLike, F_f: ArrayLike, a: ArrayLike, m: float, K: np.ndarray
) -> np.ndarray:
    """Eq. 1's residual r = K (F_app - F_f) - m a [N] (NaN near the ends)."""
    return apply_kernel(np.asarray(F_app, dtype=float) - F_f, K) - m * np.asarray(a, dtype=float)
