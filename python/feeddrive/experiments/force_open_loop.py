"""Open-loop force experiment for the moving mass (Sec. 2.4.3, last paragraph).

No controller: the amplifier reference is a square wave of +-``amplitude`` around ``bias``,
starting with a half-length pulse so that, friction and cogging aside, the velocity is a
symmetric triangle wave and the stage oscillates around its start (mid-stroke by default)
instead of drifting.  A rest of ``rest`` seconds at u = bias precedes the wave.  Where the
stage would come within ``margin`` of a stroke end the recording stops there (as an operator
would stop the drive); ``meta['stopped_at_stroke_limit']`` says so.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..data import Run
from ..fmu import Plant
from ..harness.runs import to_run
from ..harness.sensors import Sensors
from ..harness.sidecar import build_sidecar
from ..harness.simulate import simulate_open_loop
from .recording import sampled_signals, stroke


def square_wave_input(
    Ts: float,
    amplitude: float = 1.0,
    period: float = 0.2,
    n_periods: int = 10,
    bias: float = 0.0,
    rest: float = 0.1,
) -> np.ndarray:
    """u[k] [V]: ``rest`` at bias, then +amplitude for period/4, then ``2 n_periods``
    alternating half periods (-, +, ...), then -amplitude for period/4 (the ideal velocity,
    a triangle wave, starts and ends at zero), then bias."""
    n_rest = int(round(rest / Ts))
    n_half = int(round(period / (2 * Ts)))
    n_q = n_half // 2
    wave = np.concatenate(
        [np.full(n_q, 1.0)]
        + [np.full(n_half, (-1.0) ** (j + 1)) for j in range(2 * n_periods)]
        + [np.full(n_half - n_q, -1.0)]
    )
    return bias + np.concatenate([np.zeros(n_rest), amplitude * wave, [0.0]])


def force_open_loop_runs(
    params: Mapping[str, Any],
    sensors: Sensors,
    amplitude: float = 1.0,
    period: float = 0.2,
    n_periods: int = 10,
    bias: float = 0.0,
    rest: float = 0.1,
    position: float | None = None,
    margin: float = 2e-3,
    Ts: float | None = None,
    tolerance: float = 1e-6,
) -> list[Run]:
    """One open-loop run with a square-wave voltage (see the module docstring).

    Parameters
    ----------
    amplitude : +- voltage step around ``bias`` [V] (1 V is ~79 N at DC).
    period : square-wave period [s]; n_periods : number of periods.
    bias : constant voltage [V] (e.g. to balance a known drift).
    position : start position at rest [m] (default mid-stroke).
    margin : the recording stops when the true position comes this close to a stroke end.
    """
    Ts = float(params.get("Ts", 5e-4)) if Ts is None else float(Ts)
    x_min, x_max = stroke(params)
    x0 = 0.5 * (x_min + x_max) if position is None else float(position)
    u = square_wave_input(Ts, amplitude, period, n_periods, bias, rest)
    n = len(u)
    t = np.arange(n + 1) * Ts  # one sample more: see sampled_signals
    u = np.append(u, u[-1])
    F = sensors.force_disturbance(n + 1)  # the current noise acts on the stage
    with Plant(params, interface="cs", tolerance=tolerance) as plant:
        res = sampled_signals(
            simulate_open_loop(plant, t, u, F_ext=F, start_values={"x": x0, "v": 0.0})
        )
    out = np.flatnonzero((res["x"] < x_min + margin) | (res["x"] > x_max - margin))
    stop = int(out[0]) if out.size else n
    if stop < 2:
        raise ValueError(
            f"force_open_loop_runs: start position {x0} is within {margin} m "
            f"of the stroke [{x_min}, {x_max}]"
        )
    res = {k: v[:stop] for k, v in res.items()}
    meta = build_sidecar(
        "force_open_loop",
        Ts,
        None,
        sensors,
        F_load=0.0,
        name="force_open_loop",
        kind="force_open_loop",
        position=x0,
        amplitude=float(amplitude),
        period=float(period),
        n_periods=int(n_periods),
        bias=float(bias),
        rest=float(rest),
        stopped_at_stroke_limit=bool(out.size),
    )
    return [to_run(res, sensors, x_ref=None, F_load=0.0, meta=meta)]
