"""One closed-loop run of the plant FMU under a controller spec, as the harness does it."""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..experiments.measurement import Sensors, to_run
from ..experiments.references import Reference
from ..fmu import Plant, Result
from ..simulate import simulate_closed_loop
from .controllers import make_controller


def run_closed_loop(plant_params: Mapping[str, Any], spec: Mapping[str, Any], ref: Reference,
                    u_ff: np.ndarray | None = None, sensors: Sensors | None = None,
                    F_ext: np.ndarray | float = 0.0, interface: str = "cs",
                    tolerance: float = 1e-6) -> Result:
    """Simulate the closed loop: FMU with ``plant_params``, controller from ``spec``.

    With ``sensors``, the current noise acts on the stage (as a force) and the position the
    controller reads is quantised at ``sensors.quantum``; otherwise only the spec's quantum.
    """
    ctrl = make_controller(spec, ref.x, u_ff=u_ff)
    quantum = sensors.quantum if sensors is not None else float(spec.get("quantum", 1e-7))
    F = np.broadcast_to(np.asarray(F_ext, float), (ref.n + 1,)).copy()
    if sensors is not None:
        F = F + sensors.force_disturbance(ref.n + 1)
    with Plant(plant_params, interface=interface, tolerance=tolerance) as plant:
        return simulate_closed_loop(plant, ctrl, ref.n, float(ref.x[0]), Ts=ref.Ts,
                                    quantum=quantum, F_ext=F)


def measured_run(plant_params: Mapping[str, Any], spec: Mapping[str, Any], ref: Reference,
                 sensors: Sensors, u_ff: np.ndarray | None = None, meta: dict | None = None):
    """A virtual measurement (DATA.md run) of the closed loop with sensor effects."""
    res = run_closed_loop(plant_params, spec, ref, u_ff=u_ff, sensors=sensors)
    m = {"experiment": "closed_loop", "Ts": ref.Ts, "controller": dict(spec),
         "sensors": {"quantum": sensors.quantum, "current_noise": sensors.current_noise,
                     "seed": sensors.seed}}
    m.update(meta or {})
    return to_run(res, sensors, x_ref=ref.x, meta=m), res
