"""The study file (JSON, schema ``feeddrive.study/1``): what is varied, how, and what is measured.

Format::

    {"schema": "feeddrive.study/1", "name": "friction wear",
     "model": "model.json",                       # optional; default the paper's model
     "experiment": {
        "reference": {"type": "sinusoid", "amplitude": 0.005, "period": 0.4,
                      "centre": 0.15, "duration": 0.5},
        "controller": {"type": "pid"},            # a harness spec; missing keys: the type's defaults
        "sensors": {"quantum": 1e-7, "current_noise": 0.0, "seed": 0},
        "F_load": 0.0, "tolerance": 1e-6,
        "skip_start": 0.1, "half_width": 0.05,    # metric windows [s]
        "measured": "run.csv"},                   # optional: the force_residual metric's run
     "parameters": {"friction.F_s": {"low": 20.0, "high": 30.0},
                    "m": {"relative": 0.1},
                    "friction.F_c": {"distribution": "norm", "loc": 21.0, "scale": 1.0},
                    "friction.N": {"values": [3, 5, 7]}},
     "design": {"type": "lhs", "runs": 100, "seed": 1},  # grid (levels) | lhs | monte_carlo | oat
     "metrics": ["reversal_error", "rms_error", "max_error"],
     "batch_size": 8}                             # optional: runs per task

The **circular test** (ISO 230-4 on the X-Y table) is the experiment kind ``circle``, in
place of ``reference`` and ``controller``::

     "experiment": {"circle": {"radius": 0.01, "feed": 0.016667,    # [m], [m/s]
                               "feedforward": "gms",              # none | static | gms
                               "directions": ["ccw", "cw"],       # optional (H needs both)
                               "y_axis": "derived"},              # optional: derived | same
                    "tolerance": 1e-6},
     "metrics": ["circular_deviation", "hysteresis", "max_glitch"]

The run's model (the base model with the case's values) is the X axis's plant; the Y axis's
plant is derived from it (:func:`feeddrive.xy.machine.y_axis_parameters`: 40 kg,
friction x1.5, magnets a quarter pitch on) or, with ``"same"``, a copy.  Both controllers
(the Sec. 4 state-space controller with ZPETC and the named feedforward) are designed on the
*base* model (the Y one on its derived or copied base): a varied parameter is the machine
drifting from the model its controller knows.  Metrics: ``circular_deviation`` G (the larger
of the directions'), ``hysteresis`` H, ``max_glitch`` (largest |quadrant glitch|), all [m].

Paths are relative to the study file.  A parameter is a range (``low``/``high``, or
``relative``: base (1 -+ r)), a ``distribution`` of scipy.stats with its keyword arguments,
or a list of ``values`` (grid only).  :func:`load_study` raises :class:`StudyError` naming the
file and the field of the first problem.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import scipy.stats

from ..harness.controllers import CONTROLLERS
from ..harness.sensors import Sensors
from ..inputs import InputFileError, read_text
from ..model_file import PARAMETER_NAMES, ModelFile, load_model, paper_model
from ..xy.circle_test import FEEDFORWARD

SCHEMA = "feeddrive.study/1"
#: Reference profiles a study may name, and their required / optional keys.
REFERENCES: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "sinusoid": (("amplitude", "period", "centre", "duration"), ("Ts",)),
    "point_to_point": (("x_start", "x_end", "speed", "accel"), ("dwell", "Ts")),
    "back_and_forth": (("speeds",), ("stroke", "x0", "Ts", "accel", "dwell")),
}
#: Metric names a study may ask for, and the table column each gives.
METRICS: dict[str, str] = {
    "reversal_error": "reversal_error_m",
    "rms_error": "rms_error_m",
    "max_error": "max_error_m",
    "force_residual": "force_residual_N",
    "circular_deviation": "G_m",
    "hysteresis": "H_m",
    "max_glitch": "max_glitch_m",
}
#: metrics of the circle experiment (the others need a reference and a controller)
CIRCLE_METRICS = ("circular_deviation", "hysteresis", "max_glitch")
_CIRCLE = ("radius", "feed", "feedforward", "directions", "y_axis")
Y_AXES = ("derived", "same")
DESIGNS = ("grid", "lhs", "monte_carlo", "oat")
_TOP = (
    "schema",
    "kind",
    "name",
    "description",
    "model",
    "experiment",
    "parameters",
    "design",
    "metrics",
    "batch_size",
)
#: Study kinds: a parameter sweep (this module, the default) or the identification bootstrap
#: (:mod:`.bootstrap_study`).
KINDS = ("sweep", "bootstrap")
_EXPERIMENT = (
    "reference",
    "controller",
    "sensors",
    "F_load",
    "tolerance",
    "skip_start",
    "half_width",
    "measured",
    "circle",
)


class StudyError(ValueError):
    """A study file that breaks the format: names the file and the field."""

    def __init__(self, source: str, fld: str, problem: str) -> None:
        self.source, self.field, self.problem = source, fld, problem
        super().__init__(f"{source}: field {fld}: {problem}")


@dataclass(frozen=True)
class ParameterSpec:
    """How one FMU parameter varies: a range, a scipy.stats distribution, or values."""

    name: str
    base: float
    low: float | None = None
    high: float | None = None
    distribution: str | None = None
    dist_args: Mapping[str, float] = field(default_factory=dict)
    values: tuple[float, ...] | None = None

    def frozen_distribution(self) -> Any:
        """The scipy.stats frozen distribution (``uniform`` over the range when a range)."""
        if self.distribution is not None:
            return getattr(scipy.stats, self.distribution)(**self.dist_args)
        if self.low is None or self.high is None:
            raise ValueError(f"parameter {self.name}: a list of values has no distribution")
        return scipy.stats.uniform(loc=self.low, scale=self.high - self.low)


@dataclass(frozen=True)
class Experiment:
    """The closed loop every run of a study simulates (the plant parameters vary)."""

    reference: Mapping[str, Any]
    controller: Mapping[str, Any]
    sensors: Sensors
    F_load: float = 0.0
    tolerance: float = 1e-6
    skip_start: float = 0.0
    half_width: float = 0.25
    measured: Path | None = None
    #: the circular test (radius, feed, feedforward, directions, y_axis) instead of a
    #: reference and a controller (which are then empty)
    circle: Mapping[str, Any] | None = None


@dataclass(frozen=True)
class Study:
    """A validated study (see the module docstring)."""

    source: str
    name: str
    model: ModelFile
    experiment: Experiment
    parameters: tuple[ParameterSpec, ...]
    design: Mapping[str, Any]
    metrics: tuple[str, ...]
    batch_size: int | None = None
    text: str = ""  #: the file's canonical JSON (a study's identity for --resume)

    @property
    def parameter_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    @property
    def metric_columns(self) -> tuple[str, ...]:
        return tuple(METRICS[m] for m in self.metrics)


def _number(
    v: Any, src: str, fld: str, positive: bool = False, minimum: float | None = None
) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise StudyError(src, fld, f"must be a finite number, got {v!r}")
    if positive and not v > 0:
        raise StudyError(src, fld, f"must be > 0, got {v!r}")
    if minimum is not None and v < minimum:
        raise StudyError(src, fld, f"must be >= {minimum}, got {v!r}")
    return float(v)


def _integer(v: Any, src: str, fld: str, minimum: int = 1) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or v < minimum:
        raise StudyError(src, fld, f"must be an integer >= {minimum}, got {v!r}")
    return v


def _object(v: Any, src: str, fld: str, allowed: tuple[str, ...] | None = None) -> dict[str, Any]:
    if not isinstance(v, dict):
        raise StudyError(src, fld, f"must be an object, got {type(v).__name__}")
    if allowed is not None:
        bad = sorted(set(v) - set(allowed))
        if bad:
            raise StudyError(src, f"{fld}.{bad[0]}", f"unknown key (allowed: {', '.join(allowed)})")
    return v


def _reference(raw: Any, src: str) -> dict[str, Any]:
    fld = "experiment.reference"
    raw = _object(raw, src, fld)
    kind = raw.get("type")
    if kind not in REFERENCES:
        raise StudyError(
            src, f"{fld}.type", f"{kind!r} is not a reference; known: {', '.join(REFERENCES)}"
        )
    required, optional = REFERENCES[kind]
    _object(raw, src, fld, ("type",) + required + optional)
    for k in required:
        if k not in raw:
            raise StudyError(src, f"{fld}.{k}", f"missing (a {kind} needs {', '.join(required)})")
    for k, v in raw.items():
        if k == "type":
            continue
        if k == "speeds":
            if not isinstance(v, list) or not v:
                raise StudyError(src, f"{fld}.speeds", f"must be a non-empty list, got {v!r}")
            for j, s in enumerate(v):
                _number(s, src, f"{fld}.speeds[{j}]", positive=True)
        else:
            _number(
                v,
                src,
                f"{fld}.{k}",
                positive=k in ("period", "duration", "speed", "accel", "Ts", "stroke"),
            )
    return dict(raw)


def _controller(raw: Any, src: str) -> dict[str, Any]:
    fld = "experiment.controller"
    raw = _object(raw, src, fld)
    kind = raw.get("type")
    if kind not in CONTROLLERS:
        raise StudyError(
            src,
            f"{fld}.type",
            f"{kind!r} is not a controller; known: {', '.join(sorted(CONTROLLERS))}",
        )
    spec = CONTROLLERS[kind].default_spec()
    if kind == "lti" and {"A", "B", "C", "D"} & set(raw):  # the other form than the default's
        spec.pop("num"), spec.pop("den")
    spec.update(raw)
    return spec


def _sensors(raw: Any, src: str) -> Sensors:
    try:
        return Sensors.from_json(
            _object(raw, src, "experiment.sensors"), where="experiment.sensors"
        )
    except ValueError as e:
        raise StudyError(src, "experiment.sensors", str(e)) from None


def _circle(raw: Any, src: str) -> dict[str, Any]:
    fld = "experiment.circle"
    raw = _object(raw, src, fld, _CIRCLE)
    for k in ("radius", "feed"):
        if k not in raw:
            raise StudyError(
                src, f"{fld}.{k}", "missing (a circle needs radius [m] and feed [m/s])"
            )
    out: dict[str, Any] = {
        k: _number(raw[k], src, f"{fld}.{k}", positive=True) for k in ("radius", "feed")
    }
    ff = raw.get("feedforward", "none")
    if ff not in FEEDFORWARD:
        raise StudyError(src, f"{fld}.feedforward", f"{ff!r}: allowed {', '.join(FEEDFORWARD)}")
    dirs = raw.get("directions", ["ccw", "cw"])
    if (
        not isinstance(dirs, list)
        or not dirs
        or any(d not in ("ccw", "cw") for d in dirs)
        or len(set(dirs)) != len(dirs)
    ):
        raise StudyError(
            src, f"{fld}.directions", f"must be a list of 'ccw' and/or 'cw', got {dirs!r}"
        )
    y = raw.get("y_axis", "derived")
    if y not in Y_AXES:
        raise StudyError(src, f"{fld}.y_axis", f"{y!r}: allowed {', '.join(Y_AXES)}")
    out.update({"feedforward": ff, "directions": list(dirs), "y_axis": y})
    return out


def _circle_experiment(raw: dict[str, Any], src: str) -> Experiment:
    bad = sorted(set(raw) - {"circle", "tolerance"})
    if bad:
        raise StudyError(
            src,
            f"experiment.{bad[0]}",
            "not used by a circle experiment (allowed: circle, tolerance)",
        )
    return Experiment(
        reference={},
        controller={},
        sensors=Sensors(quantum=1e-7, current_noise=0.0),
        tolerance=_number(raw.get("tolerance", 1e-6), src, "experiment.tolerance", positive=True),
        circle=_circle(raw["circle"], src),
    )


def _experiment(raw: Any, src: str, folder: Path) -> Experiment:
    raw = _object(raw, src, "experiment", _EXPERIMENT)
    if "circle" in raw:
        return _circle_experiment(raw, src)
    for k in ("reference", "controller"):
        if k not in raw:
            raise StudyError(src, f"experiment.{k}", "missing")
    measured = raw.get("measured")
    if measured is not None:
        if not isinstance(measured, str):
            raise StudyError(src, "experiment.measured", f"must be a path, got {measured!r}")
        measured = folder / measured
        if not measured.is_file():
            raise StudyError(src, "experiment.measured", f"{measured}: no such file")
    return Experiment(
        reference=_reference(raw["reference"], src),
        controller=_controller(raw["controller"], src),
        sensors=_sensors(raw.get("sensors", {"current_noise": 0.0}), src),
        F_load=_number(raw.get("F_load", 0.0), src, "experiment.F_load"),
        tolerance=_number(raw.get("tolerance", 1e-6), src, "experiment.tolerance", positive=True),
        skip_start=_number(raw.get("skip_start", 0.0), src, "experiment.skip_start", minimum=0.0),
        half_width=_number(
            raw.get("half_width", 0.25), src, "experiment.half_width", positive=True
        ),
        measured=measured,
    )


def _parameter(name: str, raw: Any, base: float, src: str) -> ParameterSpec:
    fld = f"parameters[{name!r}]"
    if name not in PARAMETER_NAMES:
        raise StudyError(src, fld, "not a parameter of the model file format")
    raw = _object(raw, src, fld)
    kinds = [k for k in ("low", "relative", "distribution", "values") if k in raw]
    if len(kinds) != 1:
        raise StudyError(src, fld, "give exactly one of low/high, relative, distribution, values")
    kind = kinds[0]
    if kind == "low":
        _object(raw, src, fld, ("low", "high"))
        if "high" not in raw:
            raise StudyError(src, f"{fld}.high", "missing (a range needs low and high)")
        lo, hi = _number(raw["low"], src, f"{fld}.low"), _number(raw["high"], src, f"{fld}.high")
        if not hi > lo:
            raise StudyError(src, f"{fld}.high", f"must be > low ({lo}), got {hi}")
        return ParameterSpec(name, base, low=lo, high=hi)
    if kind == "relative":
        _object(raw, src, fld, ("relative",))
        r = _number(raw["relative"], src, f"{fld}.relative", positive=True)
        lo, hi = sorted((base * (1 - r), base * (1 + r)))
        if not hi > lo:
            raise StudyError(src, f"{fld}.relative", f"the base value is {base}: no range")
        return ParameterSpec(name, base, low=lo, high=hi)
    if kind == "values":
        _object(raw, src, fld, ("values",))
        vals = raw["values"]
        if not isinstance(vals, list) or not vals:
            raise StudyError(src, f"{fld}.values", f"must be a non-empty list, got {vals!r}")
        return ParameterSpec(
            name,
            base,
            values=tuple(_number(v, src, f"{fld}.values[{j}]") for j, v in enumerate(vals)),
        )
    dist = raw["distribution"]
    cls = getattr(scipy.stats, dist, None) if isinstance(dist, str) else None
    if not isinstance(cls, scipy.stats.rv_continuous):
        raise StudyError(
            src, f"{fld}.distribution", f"{dist!r} is not a continuous distribution of scipy.stats"
        )
    args = {k: _number(v, src, f"{fld}.{k}") for k, v in raw.items() if k != "distribution"}
    try:
        frozen = cls(**args)
        ok = math.isfinite(float(frozen.ppf(0.5)))
    except (TypeError, ValueError) as e:
        raise StudyError(src, fld, f"scipy.stats.{dist}({args}): {e}") from None
    if not ok:
        raise StudyError(src, fld, f"scipy.stats.{dist}({args}) has invalid arguments")
    return ParameterSpec(name, base, distribution=dist, dist_args=args)


def _design(raw: Any, src: str, params: tuple[ParameterSpec, ...]) -> dict[str, Any]:
    raw = _object(raw, src, "design")
    kind = raw.get("type")
    if kind not in DESIGNS:
        raise StudyError(
            src, "design.type", f"{kind!r} is not a design; known: {', '.join(DESIGNS)}"
        )
    allowed = {
        "grid": ("type", "levels"),
        "lhs": ("type", "runs", "seed"),
        "monte_carlo": ("type", "runs", "seed"),
        "oat": ("type",),
    }[kind]
    _object(raw, src, "design", allowed)
    out: dict[str, Any] = {"type": kind}
    if kind == "grid":
        out["levels"] = _integer(raw.get("levels", 3), src, "design.levels", minimum=2)
        bad = [p for p in params if p.distribution is not None]
    else:
        if kind != "oat":
            out["runs"] = _integer(raw.get("runs"), src, "design.runs")
            out["seed"] = _integer(raw.get("seed", 0), src, "design.seed", minimum=0)
        need_range = kind == "oat"
        bad = [p for p in params if p.values is not None or (need_range and p.low is None)]
    if bad:
        raise StudyError(
            src,
            f"parameters[{bad[0].name!r}]",
            f"cannot be used by a {kind} design (grid: ranges or values; lhs, "
            f"monte_carlo: ranges or distributions; oat: ranges)",
        )
    return out


def parse_study(raw: Any, source: str, folder: Path) -> Study:
    """A :class:`Study` from the decoded JSON ``raw`` (paths relative to ``folder``)."""
    raw = _object(raw, source, "(top level)", _TOP)
    if raw.get("schema") != SCHEMA:
        raise StudyError(source, "schema", f"must be {SCHEMA!r}, got {raw.get('schema')!r}")
    if raw.get("kind", "sweep") != "sweep":
        raise StudyError(
            source,
            "kind",
            f"a parameter sweep has kind 'sweep' (or none), got "
            f"{raw.get('kind')!r}: load it with load_study_file",
        )
    for k in ("experiment", "parameters", "design", "metrics"):
        if k not in raw:
            raise StudyError(source, k, "missing")
    name = raw.get("name", Path(source).stem)
    if not isinstance(name, str):
        raise StudyError(source, "name", f"must be a string, got {name!r}")
    model_ref = raw.get("model")
    if model_ref is None:
        model = paper_model()
    elif not isinstance(model_ref, str):
        raise StudyError(source, "model", f"must be a path to a model file, got {model_ref!r}")
    else:
        try:
            model = load_model(folder / model_ref)
        except (OSError, ValueError) as e:
            raise StudyError(source, "model", str(e)) from None
    experiment = _experiment(raw["experiment"], source, folder)
    praw = _object(raw["parameters"], source, "parameters")
    if not praw:
        raise StudyError(source, "parameters", "no parameter is varied")
    params = tuple(
        _parameter(n, v, float(model.parameters.get(n, 0.0)), source) for n, v in praw.items()
    )
    design = _design(raw["design"], source, params)
    metrics = raw["metrics"]
    if not isinstance(metrics, list) or not metrics:
        raise StudyError(source, "metrics", f"must be a non-empty list of {', '.join(METRICS)}")
    for j, m in enumerate(metrics):
        if m not in METRICS:
            raise StudyError(
                source, f"metrics[{j}]", f"{m!r} is not a metric; known: {', '.join(METRICS)}"
            )
    circ = experiment.circle
    circle = circ is not None
    for j, m in enumerate(metrics):
        if (m in CIRCLE_METRICS) != circle:
            raise StudyError(
                source,
                f"metrics[{j}]",
                f"{m!r} needs "
                + (
                    "a reference and a controller, not a circle"
                    if circle
                    else "a circle experiment"
                ),
            )
    if circ is not None and "hysteresis" in metrics and len(circ["directions"]) != 2:
        raise StudyError(
            source, "experiment.circle.directions", "the hysteresis metric needs both directions"
        )
    if circ is not None:
        top = float(model.parameters.get("stroke.x_max", 0.3)) - float(
            model.parameters.get("stroke.x_min", 0.0)
        )
        if not circ["radius"] < top / 2:
            raise StudyError(
                source,
                "experiment.circle.radius",
                f"{circ['radius']} m does not fit the stroke ({top} m)",
            )
    if "force_residual" in metrics and experiment.measured is None:
        raise StudyError(
            source, "experiment.measured", "the force_residual metric needs a measured run"
        )
    batch = raw.get("batch_size")
    if batch is not None:
        batch = _integer(batch, source, "batch_size")
    return Study(
        source=source,
        name=name,
        model=model,
        experiment=experiment,
        parameters=params,
        design=design,
        metrics=tuple(dict.fromkeys(metrics)),
        batch_size=batch,
        text=json.dumps(raw, sort_keys=True),
    )


def load_study(path: str | Path) -> Study:
    """Read and validate a study file; :class:`StudyError` names the file and the field."""
    path = Path(path)
    return parse_study(read_study_json(path), str(path), path.parent)


def read_study_json(path: str | Path) -> Any:
    """The decoded JSON of a study file; :class:`StudyError` when unreadable or not JSON."""
    path = Path(path)
    src = str(path)
    try:
        text = read_text(path)
    except UnicodeDecodeError as e:
        raise StudyError(src, "(file)", f"not UTF-8 text: {e}") from None
    except InputFileError as e:
        raise StudyError(src, "(file)", e.problem) from None
    except OSError as e:
        raise StudyError(src, "(file)", e.strerror or str(e)) from None
    try:
        raw = json.loads(text)
    except json.JSONDecodeError as e:
        raise StudyError(
            src, "(file)", f"invalid JSON at line {e.lineno}, column {e.colno}: {e.msg}"
        ) from None
    return raw
