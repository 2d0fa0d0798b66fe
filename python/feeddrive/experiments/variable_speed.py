"""Variable positive speed that never reverses, for the attraction parameter C (Sec. 2.4.3).

Closed-loop position reference whose speed, after a smooth start from rest, varies
sinusoidally between ``v_min`` and ``v_max`` (> 0) so that every GMS element keeps slipping
(Eq. 14).

Default 1 ... 20 mm/s with a 0.5 s period: the information on C is the frictional lag
~ (S/C) |dS/dt|, and S(|v|) changes only below ~10 V_s (31 mm/s); at 5 ... 50 mm/s S varies
by ~1.2 N and, with the paper's C = 1.08e4 N/s, ``identify.attraction`` only bounds C
(C >= 4.4e3 N/s), while 1 ... 20 mm/s at 0.5 s resolves it (~9e3 N/s, measured with the
paper's model, seeds 1 and 2).

The record ends while the stage still moves: the stop, where the speed passes through zero,
is simulated after the record (so the pre-filter sees the whole reference) but not written.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..data import Run
from ..harness.references import Reference
from ..harness.sensors import Sensors
from .recording import STROKE_MARGIN, closed_loop_measurement, stroke


def speed_profile(
    Ts: float,
    v_min: float,
    v_max: float,
    period: float,
    duration: float,
    t_start: float = 0.2,
    dwell: float = 0.0,
    t_stop: float = 0.2,
) -> tuple[np.ndarray, int, int]:
    """Speed v[k] [m/s] and the indices where the variable-speed phase begins and ends.

    ``dwell`` at rest (default none: the closed loop's unrecorded hold precedes the
    record), a raised-cosine ramp 0 -> v_min over ``t_start``, ``duration`` of
    v = v_mid - v_amp cos(2 pi t / period) (starting at v_min with zero acceleration),
    then a raised-cosine ramp to rest over ``t_stop`` and the same dwell.
    """
    if not 0 < v_min <= v_max:
        raise ValueError(f"speed_profile: need 0 < v_min <= v_max, got {v_min}, {v_max}")

    def samples(T: float) -> np.ndarray:
        return np.arange(int(round(T / Ts))) * Ts

    ramp = v_min * 0.5 * (1 - np.cos(np.pi * samples(t_start) / t_start))
    tv = samples(duration)
    vm, va = 0.5 * (v_max + v_min), 0.5 * (v_max - v_min)
    v_var = vm - va * np.cos(2 * np.pi * tv / period)
    v_end = vm - va * np.cos(2 * np.pi * duration / period)
    stop = v_end * 0.5 * (1 + np.cos(np.pi * samples(t_stop) / t_stop))
    rest = np.zeros(int(round(dwell / Ts)))
    v = np.concatenate([rest, ramp, v_var, stop, rest, [0.0]])
    k_begin = len(rest) + len(ramp)
    return v, k_begin, k_begin + len(v_var)


def variable_speed_runs(
    params: Mapping[str, Any],
    sensors: Sensors,
    v_min: float = 1e-3,
    v_max: float = 20e-3,
    period: float = 0.5,
    duration: float | None = None,
    x_start: float | None = None,
    spec: Mapping[str, Any] | None = None,
    Ts: float | None = None,
) -> list[Run]:
    """One closed-loop run at variable positive speed (never reversing).

    Parameters
    ----------
    v_min, v_max : speed range of the variable phase [m/s] (v_min > 0).
    period : period of the speed variation [s].
    duration : length of the variable phase [s] (default: what the stroke from ``x_start``
        allows at the mean speed, whole periods).
    x_start : start position at rest [m] (default stroke start + 10 mm).

    Returns ``[run]``, kind "variable_speed"; ``meta['variable_phase']`` = [t_begin, t_end] of
    the variable phase (before it, the ramp from rest); the record ends at t_end.
    """
    Ts = float(params.get("Ts", 5e-4)) if Ts is None else float(Ts)
    x_min, x_max = stroke(params)
    x0 = x_min + 2 * STROKE_MARGIN if x_start is None else float(x_start)
    v_mean = 0.5 * (v_min + v_max)
    room = x_max - STROKE_MARGIN - x0 - 0.4 * v_max  # ramps and stop distance < 0.4 v_max
    if duration is None:
        duration = period * max(1, int(room / v_mean / period))
    v, k_begin, k_end = speed_profile(Ts, v_min, v_max, period, duration)
    x = x0 + np.concatenate([[0.0], np.cumsum((v[1:] + v[:-1]) / 2 * Ts)])
    if x[-1] > x_max - STROKE_MARGIN:
        raise ValueError(
            f"variable_speed_runs: the run would end at x = {x[-1]:.4f} m, past "
            f"the stroke end {x_max} m less {STROKE_MARGIN} m; shorten duration"
        )
    ref = Reference(Ts, x, v, np.gradient(v, Ts))
    meta = {
        "name": "variable_speed",
        "kind": "variable_speed",
        "direction": 1,
        "v_min": float(v_min),
        "v_max": float(v_max),
        "period": float(period),
        "duration": float(duration),
        "x_start": x0,
        "variable_phase": [k_begin * Ts, k_end * Ts],
        "note": "recording ends at the end of the variable-speed phase, while moving",
    }
    run = closed_loop_measurement(params, sensors, ref, meta, spec)
    cols: dict[str, Any] = {c: a[: k_end + 1] for c, a in run.columns().items()}
    return [Run(**cols, meta=run.meta)]
