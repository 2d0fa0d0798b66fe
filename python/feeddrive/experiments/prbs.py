"""Current-loop identification run (Sec. 2.2): a maximum-length PRBS added to u.

The stage is held at a position (mid-stroke by default) by the closed loop; once the loop
has settled (an unrecorded hold, then ``settle`` recorded), a maximum-length sequence of
order 11 (2047 samples, one bit per sample, levels +-amplitude) is added to the
controller's output for ``periods`` full periods.  The recorded
``u`` is the total voltage applied to the amplifier (controller + PRBS), ``i`` the measured
current; the current loop's response to the PRBS is what Eq. 2 is fitted to.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..data import Run
from ..harness.references import Reference, prbs
from ..harness.sensors import Sensors
from .recording import closed_loop_measurement, stroke


def prbs_sequence(order: int = 11, amplitude: float = 0.3, periods: int = 1) -> np.ndarray:
    """``periods`` periods of the maximum-length sequence of ``order``, levels +-amplitude [V]
    (one bit per sample; :func:`feeddrive.harness.references.prbs`)."""
    return prbs(order, amplitude=amplitude, periods=periods)


def prbs_runs(
    params: Mapping[str, Any],
    sensors: Sensors,
    order: int = 11,
    amplitude: float = 0.3,
    periods: int = 2,
    settle: float = 0.1,
    position: float | None = None,
    spec: Mapping[str, Any] | None = None,
    Ts: float | None = None,
) -> list[Run]:
    """One closed-loop position-hold run with a PRBS on u.

    Parameters
    ----------
    order : order of the maximum-length sequence (period 2**order - 1 samples).
    amplitude : PRBS level [V] (+-).
    periods : full PRBS periods recorded after settling (>= 1).
    settle : recorded rest before the PRBS starts [s]; the loop has already held the
        position, unrecorded, for ``constant_speed.HOLD`` before the record starts.
    position : held position [m] (default mid-stroke).

    Returns ``[run]`` with meta kind "prbs", order, amplitude, periods, start sample, period.
    """
    Ts = float(params.get("Ts", 5e-4)) if Ts is None else float(Ts)
    x_min, x_max = stroke(params)
    x0 = 0.5 * (x_min + x_max) if position is None else float(position)
    seq = prbs_sequence(order, amplitude, periods)
    k0 = int(round(settle / Ts))
    u_ff = np.concatenate([np.zeros(k0), seq, [0.0]])  # row n: the PRBS has ended
    n = len(u_ff) - 1
    ref = Reference(Ts, np.full(n + 1, x0), np.zeros(n + 1), np.zeros(n + 1))
    meta = {
        "name": "prbs",
        "kind": "prbs",
        "position": x0,
        "order": int(order),
        "amplitude": float(amplitude),
        "periods": int(periods),
        "prbs_start": k0,
        "prbs_period": 2 ** int(order) - 1,
        "note": "u is the total applied voltage: controller output plus the PRBS",
    }
    run = closed_loop_measurement(params, sensors, ref, meta, spec, u_ff=u_ff)
    return [run]
