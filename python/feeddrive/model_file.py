"""JSON model files: which effects of the catalogue (docs/effects.md) are on, and every FMU parameter in SI.

Format::

    {"name": "paper", "description": "...",
     "effects": {"current_dynamics": true, ..., "mass": true, "offset_force": false, ...},
     "parameters": {"m": 16.1, "friction.F_s": 26.1, "friction.N": 5, ...}}

Rules (checked by :func:`load_model`, every error names the file and the key):

- ``effects`` must list every id of the effect catalogue (the registry
  ``feeddrive.effects.EFFECTS``) as a JSON boolean, and nothing else; ``mass`` must be true
  (the mass is always in the model).
- ``parameters`` keys are FMU parameter names (those of ``paper_parameters()``); an unknown
  name is an error.  **Parameters left out are filled from the paper's defaults**
  (``paper_parameters()``); the names so filled are kept in ``ModelFile.defaulted``.
- ``friction.N``, ``friction_profile.n`` and ``compliance.sensor_side`` are JSON integers;
  every other parameter a finite number (a JSON integer is accepted and stored as float).
  ``effects.<id>`` switches belong under ``effects``; one found under ``parameters`` must be a
  boolean that agrees with ``effects``.
- ``name`` (defaults to the file stem) and ``description`` are strings; other top-level
  keys and duplicate keys are errors.
- optional ``uncertainty`` (written by ``feeddrive identify --bootstrap``):
  ``{name: {"lo", "hi", "level", "replicates"}}``, each name a parameter of the file, lo and
  hi finite with lo <= hi (the value need not lie between), 0 < level < 1, replicates an
  integer >= 1; optionally ``method`` ("parametric": bias-corrected, from simulated
  campaigns; "runs": percentiles over resampled runs) and ``bias`` (the identification's
  bias the interval corrects, a finite number).  Only the identification report reads it; other commands ignore it.

- the parameters must pass the FMU's rules (m > 0, 0 <= F_c <= F_s, Ts > 0, sum(nu) = 1,
  ...): :func:`feeddrive.physics.compile` checks them with the messages of the FMU's rules
  (fmu_src/models/plant/params.c and the effect files of fmu_src/physics/), so a model the FMU
  would refuse is refused here, naming the file (or the model) first.
"""

from __future__ import annotations

import difflib
import json
import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from feeddrive.effects import EFFECTS
from feeddrive.inputs import InputFileError, read_text
from feeddrive.outputs import write_text
from feeddrive.paper import EFFECT_IDS, SWITCHABLE_EFFECTS, paper_parameters
from feeddrive.physics import ParameterError, compile

Value = float | int | bool
#: The effects without a switch: always on in a model file.
ALWAYS_ON: tuple[str, ...] = tuple(e.id for e in EFFECTS if not e.switchable)

_PAPER = paper_parameters()
#: Every FMU parameter a model file may set (effect switches excluded), in FMU order.
PARAMETER_NAMES: tuple[str, ...] = tuple(k for k in _PAPER if not k.startswith("effects."))
#: Parameters that are integers in the FMU.
INTEGER_PARAMETERS: frozenset[str] = frozenset(
    {"friction.N", "friction_profile.n", "compliance.sensor_side"}
)
_TOP_KEYS = ("name", "description", "effects", "parameters", "uncertainty")
_INTERVAL_KEYS = ("lo", "hi", "level", "replicates")
_INTERVAL_OPTIONAL = ("method", "bias")  #: how the interval was made; the bias it corrects
_METHODS = ("parametric", "runs")


class ModelFileError(ValueError):
    """A model file (or in-memory model) that breaks the format; names the source and key."""

    def __init__(self, source: str, key: str | None, problem: str):
        self.source = source
        self.key = key
        self.problem = problem
        where = source if key is None else f"{source}: key {key}"
        super().__init__(f"{where}: {problem}")


def _suggest(name: str, choices: tuple[str, ...] | list[str]) -> str:
    close = difflib.get_close_matches(name, choices, n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _check_effects(raw: Any, src: str) -> dict[str, bool]:
    if not isinstance(raw, dict):
        raise ModelFileError(src, "'effects'", f"must be an object, got {type(raw).__name__}")
    for eid, on in raw.items():
        if eid not in EFFECT_IDS:
            raise ModelFileError(
                src, f"effects[{eid!r}]", "unknown effect id" + _suggest(eid, EFFECT_IDS)
            )
        if not isinstance(on, bool):
            raise ModelFileError(src, f"effects[{eid!r}]", f"must be true or false, got {on!r}")
    missing = [e for e in EFFECT_IDS if e not in raw]
    if missing:
        raise ModelFileError(
            src,
            f"effects[{missing[0]!r}]",
            f"missing effect id(s) {', '.join(missing)}: every id of "
            "the effect catalogue must be listed",
        )
    for e in ALWAYS_ON:
        if raw[e] is not True:
            raise ModelFileError(src, f"effects[{e!r}]", f"must be true (the {e} is always on)")
    return {e: raw[e] for e in EFFECT_IDS}


def _check_value(name: str, value: Any, src: str) -> Value:
    key = f"parameters[{name!r}]"
    if name in INTEGER_PARAMETERS:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ModelFileError(src, key, f"must be an integer, got {value!r}")
        return value
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ModelFileError(src, key, f"must be a number, got {value!r}")
    if not math.isfinite(value):
        raise ModelFileError(src, key, f"must be finite, got {value!r}")
    return float(value)


def _check_parameters(
    raw: Any, effects: dict[str, bool], src: str
) -> tuple[dict[str, Value], tuple[str, ...]]:
    """Validated parameters in FMU order, and the names filled from the paper."""
    if not isinstance(raw, dict):
        raise ModelFileError(src, "'parameters'", f"must be an object, got {type(raw).__name__}")
    given: dict[str, Value] = {}
    for name, value in raw.items():
        if name.startswith("effects."):
            eid = name[len("effects.") :]
            if eid not in SWITCHABLE_EFFECTS:
                raise ModelFileError(
                    src,
                    f"parameters[{name!r}]",
                    "unknown effect switch" + _suggest(eid, SWITCHABLE_EFFECTS),
                )
            if not isinstance(value, bool):
                raise ModelFileError(
                    src, f"parameters[{name!r}]", f"must be true or false, got {value!r}"
                )
            if value != effects[eid]:
                raise ModelFileError(
                    src,
                    f"parameters[{name!r}]",
                    f"is {value} but effects[{eid!r}] is {effects[eid]}",
                )
            continue
        if name not in _PAPER:
            raise ModelFileError(
                src,
                f"parameters[{name!r}]",
                "unknown parameter name" + _suggest(name, PARAMETER_NAMES),
            )
        given[name] = _check_value(name, value, src)
    filled = tuple(n for n in PARAMETER_NAMES if n not in given)
    return {n: given[n] if n in given else _PAPER[n] for n in PARAMETER_NAMES}, filled


def _check_uncertainty(raw: Any, src: str) -> dict[str, dict[str, Any]]:
    """Validated ``uncertainty`` entries (module docstring), in FMU parameter order."""
    if not isinstance(raw, dict):
        raise ModelFileError(src, "'uncertainty'", f"must be an object, got {type(raw).__name__}")
    out: dict[str, dict[str, Any]] = {}
    for name, iv in raw.items():
        key = f"uncertainty[{name!r}]"
        if name not in _PAPER or name.startswith("effects."):
            raise ModelFileError(
                src, key, "not a parameter of the file" + _suggest(name, PARAMETER_NAMES)
            )
        if not isinstance(iv, dict):
            raise ModelFileError(src, key, f"must be an object, got {type(iv).__name__}")
        bad = sorted((set(iv) - set(_INTERVAL_OPTIONAL)) ^ set(_INTERVAL_KEYS))
        if bad:
            raise ModelFileError(
                src,
                f"{key}[{bad[0]!r}]",
                "unknown or missing key (needs "
                + ", ".join(_INTERVAL_KEYS)
                + "; may have "
                + ", ".join(_INTERVAL_OPTIONAL)
                + ")",
            )
        if "method" in iv and iv["method"] not in _METHODS:
            raise ModelFileError(
                src,
                f"{key}['method']",
                f"must be one of {', '.join(_METHODS)}, got {iv['method']!r}",
            )
        b = iv.get("bias", 0.0)
        if isinstance(b, bool) or not isinstance(b, (int, float)) or not math.isfinite(b):
            raise ModelFileError(src, f"{key}['bias']", f"must be a finite number, got {b!r}")
        for k in ("lo", "hi", "level"):
            v = iv[k]
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise ModelFileError(src, f"{key}[{k!r}]", f"must be a finite number, got {v!r}")
        if not iv["lo"] <= iv["hi"]:
            raise ModelFileError(
                src, f"{key}['hi']", f"must be >= lo = {iv['lo']!r}, got {iv['hi']!r}"
            )
        if not 0 < iv["level"] < 1:
            raise ModelFileError(src, f"{key}['level']", f"must be in (0, 1), got {iv['level']!r}")
        r = iv["replicates"]
        if isinstance(r, bool) or not isinstance(r, int) or r < 1:
            raise ModelFileError(src, f"{key}['replicates']", f"must be an integer >= 1, got {r!r}")
        out[name] = {
            "lo": float(iv["lo"]),
            "hi": float(iv["hi"]),
            "level": float(iv["level"]),
            "replicates": r,
        }
        if "method" in iv:
            out[name]["method"] = str(iv["method"])
        if "bias" in iv:
            out[name]["bias"] = float(iv["bias"])
    return {n: out[n] for n in PARAMETER_NAMES if n in out}


def _check_physics(effects: dict[str, bool], parameters: dict[str, Value], src: str) -> None:
    """The FMU's parameter rules (feeddrive.physics.compile); the FMU's message after src."""
    values: dict[str, Value] = dict(parameters)
    for eid in SWITCHABLE_EFFECTS:
        values[f"effects.{eid}"] = effects[eid]
    try:
        compile(values)
    except ParameterError as e:
        raise ModelFileError(src, None, str(e)) from None


@dataclass
class ModelFile:
    """A model: effect switches (every catalogue id) and every FMU parameter in SI.

    Construction validates like :func:`load_model`: ``parameters`` left out are filled from
    the paper's defaults (their names added to ``defaulted``) and ``effects.<id>`` keys in
    ``parameters`` are checked against ``effects`` and dropped.
    """

    name: str
    effects: dict[str, bool]
    parameters: dict[str, Value]
    description: str = ""
    #: Parameter names that were not given and took the paper's default.
    defaulted: tuple[str, ...] = field(default=(), compare=False, repr=False)
    #: Optional confidence intervals: name -> {"lo", "hi", "level", "replicates"}.
    uncertainty: dict[str, dict[str, Any]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        src = f"model {self.name!r}"
        if not isinstance(self.name, str):
            raise ModelFileError(src, "'name'", f"must be a string, got {self.name!r}")
        if not isinstance(self.description, str):
            raise ModelFileError(
                src, "'description'", f"must be a string, got {self.description!r}"
            )
        self.effects = _check_effects(dict(self.effects), src)
        self.parameters, filled = _check_parameters(dict(self.parameters), self.effects, src)
        _check_physics(self.effects, self.parameters, src)
        self.uncertainty = _check_uncertainty(dict(self.uncertainty), src)
        self.defaulted = tuple(n for n in PARAMETER_NAMES if n in filled or n in self.defaulted)

    def fmu_parameters(self) -> dict[str, Value]:
        """Every FMU parameter by name: ``parameters`` plus the ``effects.<id>`` switches
        (all ids except ``mass``, which has no switch)."""
        p: dict[str, Value] = dict(self.parameters)
        for eid in SWITCHABLE_EFFECTS:
            p[f"effects.{eid}"] = self.effects[eid]
        return p

    def with_effect(self, effect: str, on: bool = True, **params: Value) -> ModelFile:
        """A copy with ``effect`` switched ``on`` (or off) and ``params`` set.

        Parameter names contain dots, so pass them as ``**{"offset.F": 3.0}``.
        """
        src = f"model {self.name!r}"
        if effect not in EFFECT_IDS:
            raise ModelFileError(
                src, f"effects[{effect!r}]", "unknown effect id" + _suggest(effect, EFFECT_IDS)
            )
        if not isinstance(on, bool):
            raise ModelFileError(src, f"effects[{effect!r}]", f"must be a bool, got {on!r}")
        effects = dict(self.effects)
        effects[effect] = on
        parameters = dict(self.parameters)
        parameters.update(params)
        set_now = set(params)
        return replace(
            self,
            effects=effects,
            parameters=parameters,
            defaulted=tuple(n for n in self.defaulted if n not in set_now),
        )


def paper_model() -> ModelFile:
    """The paper's model (Villegas et al. 2014): its effects on, offset and asymmetry off,
    every parameter from ``feeddrive.paper.paper_parameters()``."""
    effects = {e.id: e.in_paper for e in EFFECTS}
    return ModelFile(
        name="paper",
        effects=effects,
        parameters=paper_parameters(),
        description="Villegas et al. 2014, Tables 1-3 and Eq. 2, in SI "
        "(nu_5 from Eq. 18, C = 1.08e4 N/s, see docs/model.md)",
    )


def _no_duplicates(src: str):
    def hook(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for k, v in pairs:
            if k in out:
                raise ModelFileError(src, repr(k), "duplicate key")
            out[k] = v
        return out

    return hook


def load_model(path: str | Path) -> ModelFile:
    """Read and validate a JSON model file (rules in the module docstring).

    Missing parameters are filled from the paper's defaults and listed in
    ``ModelFile.defaulted``; a missing or unknown effect id, an unknown parameter name or a
    value of the wrong type raises :class:`ModelFileError` naming the file and the key.
    """
    path = Path(path)
    src = str(path)
    try:
        text = read_text(path)
    except UnicodeDecodeError as e:
        raise ModelFileError(src, None, f"not UTF-8 text: {e}") from None
    except InputFileError as e:
        raise ModelFileError(src, None, e.problem) from None
    try:
        raw = json.loads(text, object_pairs_hook=_no_duplicates(src))
    except json.JSONDecodeError as e:
        raise ModelFileError(
            src, None, f"invalid JSON at line {e.lineno}, column {e.colno}: {e.msg}"
        ) from None
    except RecursionError:
        raise ModelFileError(src, None, "JSON nested too deeply") from None
    if not isinstance(raw, dict):
        raise ModelFileError(src, None, f"must be a JSON object, got {type(raw).__name__}")
    for k in raw:
        if k not in _TOP_KEYS:
            raise ModelFileError(
                src, repr(k), "unknown top-level key (allowed: " + ", ".join(_TOP_KEYS) + ")"
            )
    if "effects" not in raw:
        raise ModelFileError(src, "'effects'", "missing")
    name = raw.get("name", path.stem)
    description = raw.get("description", "")
    for key, value in (("name", name), ("description", description)):
        if not isinstance(value, str):
            raise ModelFileError(src, repr(key), f"must be a string, got {value!r}")
    effects = _check_effects(raw["effects"], src)
    parameters, filled = _check_parameters(raw.get("parameters", {}), effects, src)
    _check_physics(effects, parameters, src)
    uncertainty = _check_uncertainty(raw.get("uncertainty", {}), src)
    return ModelFile(
        name=name,
        effects=effects,
        parameters=parameters,
        description=description,
        defaulted=filled,
        uncertainty=uncertainty,
    )


def save_model(model: ModelFile, path: str | Path, inputs: tuple[str | Path, ...] = ()) -> None:
    """Write ``model`` as a JSON model file: every effect id and every parameter, floats
    with ``repr`` precision so :func:`load_model` gives back the same values.  The model is
    validated first (it may have been edited in place); errors name ``path`` and the key.
    The file is replaced atomically (:func:`feeddrive.outputs.write_text`); ``path`` must be
    none of ``inputs`` (:class:`feeddrive.outputs.OutputError`)."""
    src = str(path)
    effects = _check_effects(dict(model.effects), src)  # the model may have been edited
    parameters, _ = _check_parameters(dict(model.parameters), effects, src)
    _check_physics(effects, parameters, src)
    doc: dict[str, Any] = {
        "name": model.name,
        "description": model.description,
        "effects": effects,
        "parameters": parameters,
    }
    uncertainty = _check_uncertainty(dict(model.uncertainty), src)
    if uncertainty:
        doc["uncertainty"] = uncertainty
    text = json.dumps(doc, indent=2, allow_nan=False)
    write_text(path, text + "\n", inputs)
