"""Low-frequency periodic excitation at two amplitudes, for pre-rolling (Sec. 2.4.4).

Closed-loop sinusoidal position reference x_ref = centre - A cos(2 pi t / T) (starts at rest
at a reversal).  The large amplitude (default 0.5 mm) reaches gross sliding and gives the end
of pre-rolling, 2 Delta_N (~0.23 mm with the paper's Table 3).  The small one gives the slope
changes of the force-position curve at 2 Delta_1..2 Delta_N-1, so its travel 2A must pass
2 Delta_N-1 (95 um for Table 3) while staying below 2 Delta_N (228 um), i.e.
Delta_N-1 < A < Delta_N (47 ... 114 um).  The default 80 um sits well inside: 60 um, only
just above Delta_4, gave Delta_4 = 36 um (the last small-amplitude knot, at 2 Delta_4 = 95 um,
lies too close to the end of the 120 um travel to be placed), and with 30 um the knots at 73
and 95 um are never reached (Delta = 3.8, 4.9, 8.9, 22.5, 110 um; paper: 3.85, 8.99, 36.4,
47.3, 113 um).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

from ..data import Run
from ..effects import experiment_running
from ..harness.references import sinusoid
from ..harness.sensors import Sensors
from .recording import closed_loop_measurement, run_seed, stroke

#: Default amplitudes [m]: mostly pre-rolling, and gross sliding.
AMPLITUDES: tuple[float, ...] = (80e-6, 0.5e-3)


def prerolling_runs(
    params: Mapping[str, Any],
    sensors: Sensors,
    amplitudes: Sequence[float] = AMPLITUDES,
    period: float = 4.0,
    n_periods: float = 3.0,
    centre: float | None = None,
    spec: Mapping[str, Any] | None = None,
    Ts: float | None = None,
) -> list[Run]:
    """One closed-loop sinusoid run per amplitude.

    Parameters
    ----------
    amplitudes : position amplitudes A [m].
    period : period T [s]; n_periods : periods per run (the run lasts n_periods T).
    centre : centre of the motion [m] (default mid-stroke).

    Returns runs named ``<stem>_A<A in um>um`` of the experiment's kind (the experiment these
    runs are, :func:`feeddrive.effects.experiment_running`: ``prerolling_A80um``), in
    amplitude order.
    """
    x = experiment_running(prerolling_runs)
    Ts = float(params.get("Ts", 5e-4)) if Ts is None else float(Ts)
    x_min, x_max = stroke(params)
    c = 0.5 * (x_min + x_max) if centre is None else float(centre)
    runs = []
    for j, A in enumerate(amplitudes):
        if not A > 0:
            raise ValueError(f"prerolling_runs: amplitude {A!r} must be > 0")
        ref = sinusoid(float(A), period, c, n_periods * period, Ts=Ts)
        meta = {
            "name": f"{x.stem}_A{A * 1e6:g}um",
            "kind": x.kind,
            "amplitude": float(A),
            "period": float(period),
            "n_periods": float(n_periods),
            "centre": c,
            "reference": "x_ref = centre - amplitude cos(2 pi t / period)",
        }
        s = replace(sensors, seed=run_seed(sensors.seed, j))
        runs.append(closed_loop_measurement(params, s, ref, meta, spec))
    return runs
