"""One recorded run made again on a model: the same experiment, new sensor noise.

:func:`resimulate` takes a run (measured or virtual) and FMU parameters and returns the run
the model would record under the same experiment with the given :class:`Sensors`:

- a closed-loop run (the sidecar names a ``controller`` and the run has ``x_ref``): the
  same controller tracks the recorded reference, the ``F_load`` column hangs as the load,
  the unrecorded settling hold of ``hold_before_record`` is simulated first; a PRBS run
  (``kind`` ``prbs``) gets its excitation back from the sidecar's ``order``,
  ``amplitude``, ``periods`` and ``prbs_start``;
- an open-loop run (no controller, no ``x_ref``): the recorded voltage ``u`` from the
  recorded start position, at rest.

With ``current_only`` only the current is made again, ``i = G(z) u`` of the model's Eq. 2
on the recorded ``u`` plus the noise (every other column as recorded): what a PRBS run
needs for the current loop's fit (Eq. 2 relates u and i only), for a PRBS run whose sidecar
does not give the sequence or the controller.  What it cannot redo it refuses with a
ValueError naming the run and the missing field (a run without a controller in its sidecar
but with ``x_ref``, a PRBS run without its sequence).  This is what the parametric bootstrap
of the identification (:mod:`feeddrive.identify.parametric`) simulates its campaigns with.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..data import Run
from ..fmu import Plant
from ..harness.references import from_positions
from ..harness.runs import to_run
from ..harness.sensors import Sensors
from ..harness.sidecar import read_sidecar
from ..harness.simulate import simulate_open_loop
from ..physics import CurrentLoop
from ..signals import run_label, sample_time
from .prbs import prbs_sequence
from .recording import closed_loop_measurement, sampled_signals


def _prbs_excitation(run: Run, where: str) -> np.ndarray:
    """The PRBS voltage added to the controller's output, one value per recorded row."""
    meta = run.meta or {}
    keys = ("order", "amplitude", "periods", "prbs_start")
    missing = [
        k
        for k in keys
        if not isinstance(meta.get(k), (int, float)) or isinstance(meta.get(k), bool)
    ]
    if missing:
        raise ValueError(
            f"{where}: a PRBS run is simulated again from its sidecar's "
            f"{', '.join(keys)}; missing or not a number: {', '.join(missing)}"
        )
    seq = prbs_sequence(int(meta["order"]), float(meta["amplitude"]), int(meta["periods"]))
    u_ff = np.concatenate([np.zeros(int(meta["prbs_start"])), seq])
    out = np.zeros(run.n)
    out[: min(run.n, len(u_ff))] = u_ff[: run.n]
    return out


def can_resimulate(run: Run) -> str | None:
    """None when :func:`resimulate` can make ``run`` again, else why not (one sentence)."""
    where = run_label(run)
    try:
        side = read_sidecar(run.meta, where=f"{where}: sidecar")
    except ValueError as e:
        return str(e)
    if run.x_ref is not None and side.controller is None:
        return (
            f"{where}: closed-loop run (x_ref) without the controller in its sidecar: "
            "the experiment cannot be simulated again"
        )
    if run.x_ref is None and side.controller is not None:
        return f"{where}: the sidecar names a controller but the run has no x_ref column"
    if (run.meta or {}).get("kind") == "prbs":
        try:
            _prbs_excitation(run, where)
        except ValueError as e:
            return str(e)
    return None


def resimulate(
    run: Run, params: Mapping[str, Any], sensors: Sensors, current_only: bool = False
) -> Run:
    """``run``'s experiment on the plant ``params`` with ``sensors`` (see the module
    docstring); the new run keeps the sidecar's experiment keys and records ``sensors``."""
    if current_only:
        meta = dict(run.meta or {})
        meta["sensors"] = sensors.to_json()
        i = CurrentLoop.from_parameters(params).current(run.u) + sensors.current_noise_series(run.n)
        return Run(**{**run.columns(), "i": i}, meta=meta)
    why = can_resimulate(run)
    if why is not None:
        raise ValueError(why)
    side = read_sidecar(run.meta)
    Ts = side.Ts if side.Ts is not None else sample_time(run.time, label=run_label(run))
    extra = {k: v for k, v in side.extra.items() if k != "hold_before_record"}
    if side.controller is not None and run.x_ref is not None:  # both or neither: can_resimulate
        hold = float(side.extra.get("hold_before_record", 0.0))
        load = run.F_load if run.F_load is not None else np.full(run.n, side.F_load)
        u_ff = _prbs_excitation(run, run_label(run)) if extra.get("kind") == "prbs" else None
        new = closed_loop_measurement(
            params,
            sensors,
            from_positions(run.x_ref, Ts),
            extra,
            side.controller,
            F_load=float(np.mean(load)),
            u_ff=u_ff,
            hold=hold,
        )
        new.meta["experiment"] = side.experiment
        return new
    n = run.n
    t = np.arange(n + 1) * Ts
    u = np.append(np.asarray(run.u, float), run.u[-1])
    with Plant(params, interface="cs") as plant:
        res = sampled_signals(
            simulate_open_loop(
                plant,
                t,
                u,
                F_ext=sensors.force_disturbance(n + 1),
                start_values={"x": float(run.x[0]), "v": 0.0},
            )
        )
    meta = dict(run.meta or {})
    meta["sensors"] = sensors.to_json()
    return to_run(res, sensors, x_ref=None, F_load=0.0, meta=meta)
