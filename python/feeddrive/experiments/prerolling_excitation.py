"""Low-frequency periodic excitation at two amplitudes, for pre-rolling (Sec. 2.4.4).

Closed-loop sinusoidal position reference x_ref = centre - A cos(2 pi t / T) (starts at rest
at a reversal).  The small amplitude (default 30 um) keeps the stage mostly in pre-rolling
(2 Delta_5 ~ 0.23 mm with the paper's Table 3), giving the slope changes of the
force-position curve (Delta_1..N-1); the large one (default 0.5 mm) reaches gross sliding,
giving the end of pre-rolling (Delta_N).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

from ..data import Run
from .constant_speed import closed_loop_measurement, run_seed, stroke
from .measurement import Sensors
from .references import sinusoid

#: Default amplitudes [m]: mostly pre-rolling, and gross sliding.
AMPLITUDES: tuple[float, ...] = (30e-6, 0.5e-3)


def prerolling_runs(params: Mapping[str, Any], sensors: Sensors,
                    amplitudes: Sequence[float] = AMPLITUDES, period: float = 4.0,
                    n_periods: float = 3.0, centre: float | None = None,
                    spec: Mapping[str, Any] | None = None, Ts: float | None = None) -> list[Run]:
    """One closed-loop sinusoid run per amplitude.

    Parameters
    ----------
    amplitudes : position amplitudes A [m].
    period : period T [s]; n_periods : periods per run (the run lasts n_periods T).
    centre : centre of the motion [m] (default mid-stroke).

    Returns runs named ``prerolling_A<A in um>um`` (kind "prerolling"), in amplitude order.
    """
    Ts = float(params.get("Ts", 5e-4)) if Ts is None else float(Ts)
    x_min, x_max = stroke(params)
    c = 0.5 * (x_min + x_max) if centre is None else float(centre)
    runs = []
    for j, A in enumerate(amplitudes):
        if not A > 0:
            raise ValueError(f"prerolling_runs: amplitude {A!r} must be > 0")
        ref = sinusoid(float(A), period, c, n_periods * period, Ts=Ts)
        meta = {"name": f"prerolling_A{A * 1e6:g}um", "kind": "prerolling",
                "amplitude": float(A), "period": float(period), "n_periods": float(n_periods),
                "centre": c, "reference": "x_ref = centre - amplitude cos(2 pi t / period)"}
        s = replace(sensors, seed=run_seed(sensors.seed, j))
        runs.append(closed_loop_measurement(params, s, ref, meta, spec))
    return runs
