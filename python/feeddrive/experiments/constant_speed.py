"""Constant-speed runs through the closed loop (Secs. 2.3.1 and 2.4.2).

Each run is a trapezoidal position reference (``harness.references.point_to_point``) over a segment
of the stroke, in one direction, with a constant pulley load P.  The load enters the FMU as
``F_ext = P`` (same sign convention as cogging: m a = K_f i - F_cg - F_f - F_ext) and is the
run's ``F_load`` column.  Before the record the drive holds the start position with the
load hung (unrecorded, see :func:`closed_loop_measurement`).  Nothing else is dropped: the
dwell at rest and the acceleration ramps are in the record (identification crops them).

- :func:`cogging_ripple_runs`: the paper's six runs, +-1 mm/s with P = 0, 54.9, 272.7 N.
- :func:`stribeck_runs`: unloaded runs at several speeds in both directions; the segment of
  each speed is sized so that its cruise lasts about ``cruise_time``.

Also :func:`closed_loop_measurement`, the one closed-loop virtual measurement that the other
closed-loop experiments (PRBS, variable speed, pre-rolling) share.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from ..data import Run
from ..effects import experiment_running
from ..harness.references import point_to_point
from ..harness.sensors import Sensors
from .recording import STROKE_MARGIN, closed_loop_measurement, run_seed, stroke

#: Pulley loads of the paper's ripple/cogging runs [N] (Sec. 2.3.1).
PAPER_LOADS: tuple[float, ...] = (0.0, 54.9, 272.7)
#: Speed of the paper's ripple/cogging runs [m/s].
PAPER_SPEED: float = 1e-3
#: Speed of the campaign's whole-stroke ripple/cogging runs [m/s]: Eqs. 4-7 need the current
#: at constant speed over the stroke, not the paper's 1 mm/s; at 20 mm/s a run is 15 s of
#: cruise instead of 290 s, and the maps identify within the same tolerances.
MAP_SPEED: float = 20e-3
#: Default speeds of the Stribeck runs [m/s] (unloaded, each over at least one magnet pitch).
STRIBECK_SPEEDS: tuple[float, ...] = (
    0.3e-3,
    0.6e-3,
    1e-3,
    2e-3,
    4e-3,
    8e-3,
    15e-3,
    30e-3,
    60e-3,
    120e-3,
)


def _tag(speed: float, direction: int, P: float) -> str:
    sign = "p" if direction > 0 else "m"
    return f"cv_{sign}{speed * 1e3:g}mm_s_P{P:g}"


def constant_speed_runs(
    params: Mapping[str, Any],
    sensors: Sensors,
    speeds: Sequence[float] = (PAPER_SPEED,),
    loads: Sequence[float] = (0.0,),
    segment: tuple[float, float] | None = None,
    directions: Sequence[int] = (1, -1),
    accel: float = 0.5,
    dwell: float = 0.5,
    spec: Mapping[str, Any] | None = None,
    Ts: float | None = None,
) -> list[Run]:
    """Closed-loop trapezoid runs at each |speed|, load and direction.

    Parameters
    ----------
    speeds : cruise speeds [m/s] (> 0).
    loads : pulley loads P [N].
    segment : (x_lo, x_hi) [m] covered by every run (default: the stroke less 5 mm at each
        end); a positive run goes x_lo -> x_hi, a negative one x_hi -> x_lo, from rest.
    directions : +1 and/or -1.
    accel : acceleration of the ramps [m/s^2]; dwell : rest before and after [s].
    Ts : sample time (default params['Ts'], else 0.5 ms).

    Returns runs named ``cv_<p|m><speed in mm/s>mm_s_P<load>`` (in ``meta['name']``), in the
    order speed, load, direction; run j's noise seed is derived from ``sensors.seed`` and j.
    """
    lo, hi = segment if segment is not None else _default_segment(params)
    if not hi > lo:
        raise ValueError(f"constant_speed_runs: segment {(lo, hi)} must have x_hi > x_lo")
    Ts = float(params.get("Ts", 5e-4)) if Ts is None else float(Ts)
    runs: list[Run] = []
    for v in speeds:
        if not v > 0:
            raise ValueError(f"constant_speed_runs: speed {v!r} must be > 0 (give |v|)")
        for P in loads:
            for d in directions:
                if d not in (1, -1):
                    raise ValueError(f"constant_speed_runs: direction {d!r} must be +1 or -1")
                x0, x1 = (lo, hi) if d > 0 else (hi, lo)
                ref = point_to_point(x0, x1, float(v), accel, dwell=dwell, Ts=Ts)
                name = _tag(float(v), d, float(P))
                meta = {
                    "name": name,
                    "kind": "constant_speed",
                    "speed": float(v),
                    "direction": int(d),
                    "P": float(P),
                    "segment": [float(x0), float(x1)],
                    "accel": float(accel),
                    "dwell": float(dwell),
                }
                s = replace(sensors, seed=run_seed(sensors.seed, len(runs)))
                runs.append(closed_loop_measurement(params, s, ref, meta, spec, F_load=P))
    return runs


def _default_segment(params: Mapping[str, Any]) -> tuple[float, float]:
    x_min, x_max = stroke(params)
    return x_min + STROKE_MARGIN, x_max - STROKE_MARGIN


def cogging_ripple_runs(
    params: Mapping[str, Any],
    sensors: Sensors,
    speed: float = PAPER_SPEED,
    loads: Sequence[float] = PAPER_LOADS,
    segment: tuple[float, float] | None = None,
    **options: Any,
) -> list[Run]:
    """The paper's six ripple/cogging runs: +-``speed`` with each load (Eqs. 4, 5).

    ``segment`` defaults to the whole stroke less 5 mm at each end (300 s per run at
    1 mm/s); other options go to :func:`constant_speed_runs`.
    """
    return constant_speed_runs(
        params, sensors, speeds=(speed,), loads=loads, segment=segment, **options
    )


def stribeck_runs(
    params: Mapping[str, Any],
    sensors: Sensors,
    speeds: Sequence[float] = STRIBECK_SPEEDS,
    cruise_time: float = 60.0,
    min_length: float = 0.0375,
    max_length: float = 0.24,
    centre: float | None = None,
    **options: Any,
) -> list[Run]:
    """Unloaded constant-speed runs in both directions at each speed (Eq. 13).

    Each speed's segment is centred on ``centre`` (default mid-stroke) with length
    ``clip(speed * cruise_time, min_length, max_length)`` plus the two ramp distances
    (default: at least one magnet pitch, 37.5 mm, so Eq. 13 averages over a pitch).
    Run j's noise seed is derived from ``sensors.seed``, the group of the experiment these
    runs are (:func:`feeddrive.effects.experiment_running`) and j.
    """
    x_min, x_max = stroke(params)
    c = 0.5 * (x_min + x_max) if centre is None else float(centre)
    accel = float(options.get("accel", 0.5))
    key = experiment_running(stribeck_runs).group  # the noise seeds' key
    runs = []
    for j, v in enumerate(speeds):
        half = 0.5 * float(np.clip(v * cruise_time, min_length, max_length)) + v**2 / (2 * accel)
        lo, hi = max(c - half, x_min + STROKE_MARGIN), min(c + half, x_max - STROKE_MARGIN)
        s = replace(sensors, seed=run_seed(sensors.seed, key, j))
        runs += constant_speed_runs(
            params, s, speeds=(v,), loads=(0.0,), segment=(lo, hi), **options
        )
    return runs
