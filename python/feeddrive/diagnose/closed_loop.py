"""The closed-loop gap: the position error of a model re-simulated with each run's
controller, overall and right after reversals."""

from __future__ import annotations

import numpy as np

from ..data import Run
from ..harness.runs import replay
from ..harness.sidecar import read_sidecar
from ..model_file import ModelFile
from .localise import displacement_since_reversal

#: Travel after a reversal [m] within which the closed-loop error counts as reversal error.
REVERSAL_ZONE = 1e-3


def closed_loop_gap(runs: list[Run], model: ModelFile) -> dict | None:
    """Closed-loop position error of ``model`` re-simulated with each run's controller.

    Only runs that have ``x_ref`` and whose sidecar (:mod:`feeddrive.harness.sidecar`)
    names a controller the registry builds (:data:`~feeddrive.harness.controllers.
    CONTROLLERS`) count; None when there is none.  The replay
    (:func:`feeddrive.harness.runs.replay`) reads the position at the run's
    ``sensors.quantum``, without noise, under the run's load.  Returns rms and max
    |x_sim - x_meas| [m], and the max within ``REVERSAL_ZONE`` of travel after a reversal
    (the reversal error).
    """
    errs, near = [], []
    for run in runs:
        side = read_sidecar(run.meta, where=f"{run.path or run.name}: sidecar", run=run)
        if side.controller is None or run.x_ref is None:
            continue
        x_sim = replay(model.fmu_parameters(), run, side)
        errs.append(side.sensors.quantise(x_sim) - np.asarray(run.x))
        near.append(displacement_since_reversal(np.asarray(run.x)) < REVERSAL_ZONE)
    if not errs:
        return None
    e = np.concatenate(errs)
    nz = np.concatenate(near)
    return {
        "position_error_rms_m": float(np.sqrt(np.mean(e**2))),
        "position_error_max_m": float(np.max(np.abs(e))),
        "reversal_error_max_m": float(np.max(np.abs(e[nz]))) if nz.any() else None,
    }
