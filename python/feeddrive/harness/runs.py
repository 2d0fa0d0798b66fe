"""Closed-loop runs from a controller spec, and the run maker: a Result -> a recording (Run).

:func:`run_closed_loop` simulates the FMU under the controller a spec describes;
:func:`to_run` applies the sensor model to a result (what a measurement records);
:func:`closed_loop_run` does both and gives the run its sidecar (:mod:`.sidecar`);
:func:`replay` re-simulates a run's closed loop from its sidecar (validate, diagnose).
Write the run with :func:`feeddrive.data.write_run`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..data import Run
from ..fmu import Plant, Result
from .controllers import make_controller
from .references import Reference, from_positions
from .sensors import Sensors
from .sidecar import Sidecar, build_sidecar, read_sidecar
from .simulate import simulate_closed_loop

#: The scale the loop reads when no sensor model is given: 100 nm, no current noise.
SCALE_ONLY = Sensors(quantum=1e-7, current_noise=0.0)


def run_closed_loop(
    plant_params: Mapping[str, Any],
    spec: Mapping[str, Any],
    ref: Reference,
    u_ff: np.ndarray | None = None,
    sensors: Sensors = SCALE_ONLY,
    F_ext: np.ndarray | float = 0.0,
    interface: str = "cs",
    tolerance: float = 1e-6,
) -> Result:
    """Simulate the closed loop: the FMU with ``plant_params``, the controller of ``spec``.

    The controller reads the position quantised at ``sensors.quantum``; a current noise
    that acts on the stage (``sensors.noise_on_stage``) enters as a force.  ``u_ff`` [V] is
    added to the controller's output (see :func:`~.controllers.make_controller`).
    """
    ctrl = make_controller(spec, ref, u_ff=u_ff)
    F = np.broadcast_to(np.asarray(F_ext, float), (ref.n + 1,)) + sensors.force_disturbance(
        ref.n + 1
    )
    with Plant(plant_params, interface=interface, tolerance=tolerance) as plant:
        return simulate_closed_loop(
            plant, ctrl, ref.n, float(ref.x[0]), Ts=ref.Ts, quantum=sensors.quantum, F_ext=F
        )


def to_run(
    res: Mapping[str, np.ndarray],
    sensors: Sensors,
    x_ref: np.ndarray | None = None,
    F_load: float | np.ndarray = 0.0,
    meta: Mapping[str, Any] | None = None,
) -> Run:
    """A recording from simulated signals: x quantised, the current noise added to i."""
    n = len(res["time"])
    return Run(
        time=np.asarray(res["time"], float),
        u=np.asarray(res["u"], float),
        x=sensors.quantise(res["x_measured"] if "x_measured" in res else res["x"]),
        i=np.asarray(res["i"], float) + sensors.current_noise_series(n),
        x_ref=None if x_ref is None else np.asarray(x_ref, float),
        F_load=np.broadcast_to(np.asarray(F_load, float), (n,)).copy(),
        meta=dict(meta or {}),
    )


def closed_loop_run(
    plant_params: Mapping[str, Any],
    spec: Mapping[str, Any],
    ref: Reference,
    sensors: Sensors,
    experiment: str = "closed_loop",
    F_load: float = 0.0,
    u_ff: np.ndarray | None = None,
    **extra: Any,
) -> tuple[Run, Result]:
    """A virtual measurement of the closed loop: the run (with its sidecar) and the result.

    ``F_load`` [N] is a constant pulley load (F_ext); ``extra`` keys go to the sidecar.
    """
    res = run_closed_loop(plant_params, spec, ref, u_ff=u_ff, sensors=sensors, F_ext=F_load)
    meta = build_sidecar(experiment, ref.Ts, spec, sensors, F_load=F_load, **extra)
    return to_run(res, sensors, x_ref=ref.x, F_load=F_load, meta=meta), res


def replay(plant_params: Mapping[str, Any], run: Run, side: Sidecar | None = None) -> np.ndarray:
    """The position [m] the model gives under a run's own closed loop, sample by sample.

    The run's sidecar (``side``, default read from ``run.meta``) gives the controller, Ts,
    the scale quantum (read without noise: this is the model's prediction) and
    ``hold_before_record`` (the settling hold the recording skipped is simulated again);
    the reference is ``run.x_ref``, the load the ``F_load`` column (else the sidecar's).
    ValueError, naming the run, when the run has no ``x_ref`` or no controller, or the
    controller spec is bad.
    """
    where = f"{run.path or run.name}: sidecar"
    side = read_sidecar(run.meta, where=where) if side is None else side
    if side.controller is None or run.x_ref is None:
        raise ValueError(f"{where}: a replay needs a controller and an x_ref column")
    Ts = side.Ts if side.Ts is not None else run.Ts
    hold = side.extra.get("hold_before_record", 0.0)
    if isinstance(hold, bool) or not isinstance(hold, (int, float)) or not hold >= 0:
        raise ValueError(f"{where}: hold_before_record = {hold!r} must be a number >= 0 [s]")
    k0 = int(round(hold / Ts))
    load = run.F_load if run.F_load is not None else np.full(run.n, side.F_load)
    x = np.concatenate([np.full(k0, run.x_ref[0]), run.x_ref])
    F = np.concatenate([np.full(k0, load[0]), load])
    scale = Sensors(quantum=side.sensors.quantum, current_noise=0.0)
    try:
        sim = run_closed_loop(
            plant_params, side.controller, from_positions(x, Ts), sensors=scale, F_ext=F
        )
    except ValueError as e:
        raise ValueError(f"{where}: {e}") from None
    return np.asarray(sim["x_measured"][k0 : k0 + run.n])
