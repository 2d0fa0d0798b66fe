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

The fields are read by :mod:`.fields` (numbers, integers, objects), :mod:`.experiment_field`
and :mod:`.parameters_field` (the parameters and the design) into the records of
:mod:`.spec`.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ..inputs import InputFileError, read_text
from ..model_file import load_model, paper_model
from .experiment_field import experiment_field
from .fields import StudyError, integer_field, object_field
from .parameters_field import design_field, parameter_field
from .spec import CIRCLE_METRICS, METRICS, Experiment, ParameterSpec, Study

__all__ = [
    "CIRCLE_METRICS",
    "KINDS",
    "METRICS",
    "SCHEMA",
    "Experiment",
    "ParameterSpec",
    "Study",
    "StudyError",
    "load_study",
    "parse_study",
    "read_study_json",
]

SCHEMA = "feeddrive.study/1"
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


def parse_study(raw: Any, source: str, folder: Path) -> Study:
    """A :class:`Study` from the decoded JSON ``raw`` (paths relative to ``folder``)."""
    raw = object_field(raw, source, "(top level)", _TOP)
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
    experiment = experiment_field(raw["experiment"], source, folder)
    praw = object_field(raw["parameters"], source, "parameters")
    if not praw:
        raise StudyError(source, "parameters", "no parameter is varied")
    params = tuple(
        parameter_field(n, v, float(model.parameters.get(n, 0.0)), source) for n, v in praw.items()
    )
    design = design_field(raw["design"], source, params)
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
        batch = integer_field(batch, source, "batch_size")
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
