"""A study file's ``experiment``: the reference, the controller spec (the type's defaults for
missing keys), the sensors, the metric windows, the measured run, or the circular test."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..harness.controllers import CONTROLLERS
from ..harness.sensors import Sensors
from ..xy.circle_test import FEEDFORWARD
from .fields import StudyError, number_field, object_field, typed_object_field
from .spec import Experiment

#: Reference profiles a study may name, and their required / optional keys.
REFERENCES: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "sinusoid": (("amplitude", "period", "centre", "duration"), ("Ts",)),
    "point_to_point": (("x_start", "x_end", "speed", "accel"), ("dwell", "Ts")),
    "back_and_forth": (("speeds",), ("stroke", "x0", "Ts", "accel", "dwell")),
}
_CIRCLE = ("radius", "feed", "feedforward", "directions", "y_axis")
Y_AXES = ("derived", "same")
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


def _reference(raw: Any, src: str) -> dict[str, Any]:
    fld = "experiment.reference"
    raw, kind = typed_object_field(raw, src, fld, REFERENCES, "reference")
    required, optional = REFERENCES[kind]
    object_field(raw, src, fld, ("type",) + required + optional)
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
                number_field(s, src, f"{fld}.speeds[{j}]", positive=True)
        else:
            number_field(
                v,
                src,
                f"{fld}.{k}",
                positive=k in ("period", "duration", "speed", "accel", "Ts", "stroke"),
            )
    return dict(raw)


def _controller(raw: Any, src: str) -> dict[str, Any]:
    fld = "experiment.controller"
    raw, kind = typed_object_field(raw, src, fld, CONTROLLERS, "controller", sorted(CONTROLLERS))
    spec = CONTROLLERS[kind].default_spec()
    if kind == "lti" and {"A", "B", "C", "D"} & set(raw):  # the other form than the default's
        spec.pop("num"), spec.pop("den")
    spec.update(raw)
    return spec


def _sensors(raw: Any, src: str) -> Sensors:
    try:
        return Sensors.from_json(
            object_field(raw, src, "experiment.sensors"), where="experiment.sensors"
        )
    except ValueError as e:
        raise StudyError(src, "experiment.sensors", str(e)) from None


def _circle(raw: Any, src: str) -> dict[str, Any]:
    fld = "experiment.circle"
    raw = object_field(raw, src, fld, _CIRCLE)
    for k in ("radius", "feed"):
        if k not in raw:
            raise StudyError(
                src, f"{fld}.{k}", "missing (a circle needs radius [m] and feed [m/s])"
            )
    out: dict[str, Any] = {
        k: number_field(raw[k], src, f"{fld}.{k}", positive=True) for k in ("radius", "feed")
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
        tolerance=number_field(
            raw.get("tolerance", 1e-6), src, "experiment.tolerance", positive=True
        ),
        circle=_circle(raw["circle"], src),
    )


def experiment_field(raw: Any, src: str, folder: Path) -> Experiment:
    """The study's ``experiment``: a reference, a controller and the sensors, or a circle
    (paths relative to ``folder``)."""
    raw = object_field(raw, src, "experiment", _EXPERIMENT)
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
        F_load=number_field(raw.get("F_load", 0.0), src, "experiment.F_load"),
        tolerance=number_field(
            raw.get("tolerance", 1e-6), src, "experiment.tolerance", positive=True
        ),
        skip_start=number_field(
            raw.get("skip_start", 0.0), src, "experiment.skip_start", minimum=0.0
        ),
        half_width=number_field(
            raw.get("half_width", 0.25), src, "experiment.half_width", positive=True
        ),
        measured=measured,
    )
