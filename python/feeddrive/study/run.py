"""One study run: the base model with the case's parameter values, the study's closed loop,
the metrics; a run that fails is a row with its status and message, never an exception.

Each process builds the reference and the controller of an experiment once and resets the
controller before every run (:func:`feeddrive.harness.simulate_closed_loop` does), keeps one
Plant per tolerance (each run starts a fresh FMI instance on it with the run's parameters:
no new fmpy wrapper per run), and reads a measured run once.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from ..data import Run, load_run
from ..fmu import Plant
from ..harness.controllers import Controller, make_controller
from ..harness.references import Reference, back_and_forth, point_to_point, sinusoid
from ..harness.simulate import simulate_closed_loop
from ..model_file import ModelFile
from ..xy.circle_test import circular_case, controller_values
from ..xy.machine import AxisModel, y_axis_parameters
from .metrics import residual_metric, select, tracking_metrics
from .samplers import Case
from .spec import CIRCLE_METRICS, METRICS, Experiment, Study

OK, FAILED = "ok", "failed"
_PROFILES: dict[str, Callable[..., Reference]] = {
    "sinusoid": sinusoid,
    "point_to_point": point_to_point,
    "back_and_forth": back_and_forth,
}


@dataclass(frozen=True)
class RunTask:
    """What a worker needs for any run of a study (picklable)."""

    model: ModelFile
    experiment: Experiment
    metrics: tuple[str, ...]
    parameter_names: tuple[str, ...]

    @classmethod
    def of(cls, study: Study) -> RunTask:
        return cls(study.model, study.experiment, study.metrics, study.parameter_names)


def make_reference(spec: dict[str, Any]) -> Reference:
    """The harness reference a study's ``experiment.reference`` names."""
    kw = {k: v for k, v in spec.items() if k != "type"}
    return _PROFILES[spec["type"]](**kw)


class _ProcessCache:
    """Reference + controller per experiment, one Plant per tolerance, measured runs per path,
    in this process."""

    def __init__(self) -> None:
        self.loops: dict[str, tuple[Reference, Controller]] = {}
        self.runs: dict[str, Run] = {}
        self.plants: dict[float, Plant] = {}
        self.circle_controllers: dict[str, list[dict[str, Any]]] = {}

    def plant(self, parameters: dict[str, Any], tolerance: float) -> Plant:
        """The process's Plant at ``tolerance``, to be started with ``parameters``."""
        if tolerance not in self.plants:
            self.plants[tolerance] = Plant(tolerance=tolerance)
        plant = self.plants[tolerance]
        plant.parameters = dict(parameters)  # applied by the next start()
        return plant

    def loop(self, exp: Experiment) -> tuple[Reference, Controller]:
        key = json.dumps([exp.reference, exp.controller], sort_keys=True, default=str)
        if key not in self.loops:
            if len(self.loops) > 8:
                self.loops.clear()
            ref = make_reference(dict(exp.reference))
            self.loops[key] = (ref, make_controller(exp.controller, ref))
        return self.loops[key]

    def measured(self, path: Path) -> Run:
        key = str(path)
        if key not in self.runs:
            self.runs[key] = load_run(path)
        return self.runs[key]


_CACHE = _ProcessCache()


def _simulate(model: ModelFile, exp: Experiment) -> dict[str, float]:
    ref, ctrl = _CACHE.loop(exp)
    F = exp.F_load + exp.sensors.force_disturbance(ref.n + 1)
    plant = _CACHE.plant(model.fmu_parameters(), exp.tolerance)
    res = simulate_closed_loop(
        plant, ctrl, ref.n, float(ref.x[0]), Ts=ref.Ts, quantum=exp.sensors.quantum, F_ext=F
    )
    return tracking_metrics(ref.x, res["x"], ref.Ts, exp)


def _y_of(params: dict[str, Any], how: str) -> dict[str, Any]:
    return dict(params) if how == "same" else y_axis_parameters(params)


def _circle(base: ModelFile, model: ModelFile, exp: Experiment) -> dict[str, float]:
    """G, H, max glitch of the circular test: the run's model is the X plant (schema)."""
    c = exp.circle
    assert c is not None
    nom_x = base.fmu_parameters()
    plant_x = model.fmu_parameters()
    axes = (
        AxisModel("X", nom_x, plant_x, "study"),
        AxisModel("Y", _y_of(nom_x, c["y_axis"]), _y_of(plant_x, c["y_axis"]), "study"),
    )
    key = json.dumps([c, nom_x], sort_keys=True, default=str)
    if key not in _CACHE.circle_controllers:
        _CACHE.circle_controllers.clear()
        _CACHE.circle_controllers[key] = [controller_values(a, c["feedforward"]) for a in axes]
    case = circular_case(
        axes,
        c["radius"],
        c["feed"],
        c["feedforward"],
        c["directions"],
        tolerance=exp.tolerance,
        controllers=_CACHE.circle_controllers[key],
    )
    G = max(r.trace.G for r in case.runs.values())
    return {"G_m": G, "H_m": case.H, "max_glitch_m": case.max_glitch()}


def run_case(task: RunTask, case: Case) -> dict[str, Any]:
    """The table row of one case: run, label, parameters, metrics, wall_s, status, message."""
    t0 = time.perf_counter()
    row: dict[str, Any] = {"run": case.run, "label": case.label}
    row.update({n: case.values[n] for n in task.parameter_names})
    values: dict[str, float] = {c: float("nan") for c in METRICS.values()}
    try:
        params = dict(task.model.parameters)
        params.update(case.values)
        model = replace(task.model, parameters=params)  # validated like a model file
        tracking = ("reversal_error", "rms_error", "max_error")
        if any(m in task.metrics for m in tracking):
            values.update(_simulate(model, task.experiment))
        if any(m in task.metrics for m in CIRCLE_METRICS):
            values.update(_circle(task.model, model, task.experiment))
        if "force_residual" in task.metrics:
            if task.experiment.measured is None:
                raise ValueError("force_residual: the experiment names no measured run")
            values["force_residual_N"] = residual_metric(
                _CACHE.measured(task.experiment.measured), model
            )
        status, message = OK, ""
    except Exception as e:  # a failed run is a row (any error of the model, FMU, metric)
        status, message = FAILED, f"{type(e).__name__}: {e}".replace("\n", " ")
    row.update(select(values, task.metrics))
    row.update({"wall_s": time.perf_counter() - t0, "status": status, "message": message})
    return row


def run_batch(task: RunTask, batch: Sequence[Case]) -> list[dict[str, Any]]:
    """:func:`run_case` of every case of a batch (one task of the executor)."""
    return [run_case(task, c) for c in batch]
