"""Tests of feeddrive.model_file: paper round trip, strict keys and types, with_effect."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from feeddrive.cli import main
from feeddrive.model_file import (
    PARAMETER_NAMES,
    ModelFile,
    ModelFileError,
    load_model,
    paper_model,
    save_model,
)
from feeddrive.paper import EFFECT_IDS, SWITCHABLE_EFFECTS, paper_parameters


def _doc() -> dict:
    m = paper_model()
    return {
        "name": "t",
        "description": "test",
        "effects": dict(m.effects),
        "parameters": dict(m.parameters),
    }


def _write(tmp_path: Path, doc: dict | str, name: str = "model.json") -> Path:
    p = tmp_path / name
    p.write_text(doc if isinstance(doc, str) else json.dumps(doc, indent=1))
    return p


def _error(path: Path) -> str:
    with pytest.raises(ModelFileError) as err:
        load_model(path)
    msg = str(err.value)
    assert str(path) in msg, msg
    return msg


def test_paper_model_is_paper_parameters():
    m = paper_model()
    assert m.fmu_parameters() == paper_parameters()
    assert set(m.effects) == set(EFFECT_IDS) and m.effects["mass"] is True
    assert m.effects["offset_force"] is False and m.effects["asymmetric_friction"] is False
    assert m.parameters["m"] == 16.1 and m.parameters["friction.sigma2"] == pytest.approx(54.0)
    assert m.parameters["friction.N"] == 5 and isinstance(m.parameters["friction.N"], int)
    assert m.defaulted == ()


def test_paper_round_trip_exact(tmp_path):
    m = paper_model()
    path = tmp_path / "paper.json"
    save_model(m, path)
    back = load_model(path)
    assert back == m
    for k, v in m.parameters.items():  # same bits, same type
        assert type(back.parameters[k]) is type(v) and back.parameters[k] == v, k
    assert back.defaulted == ()
    doc = json.loads(path.read_text())
    assert list(doc["effects"]) == EFFECT_IDS
    assert list(doc["parameters"]) == list(PARAMETER_NAMES)
    assert not any(k.startswith("effects.") for k in doc["parameters"])


def test_fmu_parameters_has_switches_but_no_mass_switch():
    p = paper_model().fmu_parameters()
    assert p["effects.prerolling"] is True
    assert p["effects.frictional_lag"] is True
    assert p["effects.offset_force"] is False
    assert "effects.mass" not in p
    assert {k for k in p if k.startswith("effects.")} == {
        f"effects.{e}" for e in SWITCHABLE_EFFECTS
    }


def test_missing_parameters_filled_from_paper(tmp_path):
    doc = _doc()
    doc["parameters"] = {"m": 20, "friction.F_s": 30.5}
    m = load_model(_write(tmp_path, doc))
    assert m.parameters["m"] == 20.0 and isinstance(m.parameters["m"], float)
    assert m.parameters["friction.F_s"] == 30.5
    assert m.parameters["friction.F_c"] == paper_parameters()["friction.F_c"]
    assert "m" not in m.defaulted and "friction.F_c" in m.defaulted
    assert len(m.defaulted) == len(PARAMETER_NAMES) - 2


def test_name_defaults_to_stem_and_parameters_may_be_absent(tmp_path):
    doc = _doc()
    del doc["name"], doc["parameters"]
    m = load_model(_write(tmp_path, doc, "mine.json"))
    assert m.name == "mine" and m.fmu_parameters() == paper_parameters()


def test_unknown_effect_rejected_with_its_name(tmp_path):
    doc = _doc()
    doc["effects"]["backlash"] = True
    msg = _error(_write(tmp_path, doc))
    assert "effects['backlash']" in msg and "unknown effect id" in msg


def test_misspelt_effect_gets_suggestion(tmp_path):
    doc = _doc()
    doc["effects"]["prerollling"] = doc["effects"].pop("prerolling")
    msg = _error(_write(tmp_path, doc))
    assert "prerollling" in msg and "did you mean 'prerolling'" in msg


def test_missing_effect_rejected_with_its_name(tmp_path):
    doc = _doc()
    del doc["effects"]["viscous"]
    msg = _error(_write(tmp_path, doc))
    assert "effects['viscous']" in msg and "missing" in msg


def test_mass_must_be_on(tmp_path):
    doc = _doc()
    doc["effects"]["mass"] = False
    assert "effects['mass']" in _error(_write(tmp_path, doc))


def test_unknown_parameter_rejected_with_its_name(tmp_path):
    doc = _doc()
    doc["parameters"]["friction.Fs"] = 26.1
    msg = _error(_write(tmp_path, doc))
    assert "parameters['friction.Fs']" in msg and "did you mean 'friction.F_s'" in msg


def test_unknown_top_level_key_rejected(tmp_path):
    doc = _doc()
    doc["effect"] = {}
    assert "'effect'" in _error(_write(tmp_path, doc))


@pytest.mark.parametrize(
    "section,key,value,word",
    [
        ("effects", "stribeck", "yes", "true or false"),
        ("effects", "stribeck", 1, "true or false"),
        ("parameters", "friction.N", 5.5, "integer"),
        ("parameters", "friction.N", True, "integer"),
        ("parameters", "m", "16.1", "number"),
        ("parameters", "m", True, "number"),
        ("parameters", "m", None, "number"),
        ("parameters", "friction.C", math.nan, "finite"),
        ("parameters", "friction.C", math.inf, "finite"),
        ("parameters", "effects.stribeck", "on", "true or false"),
        ("parameters", "effects.stribeck", False, "effects['stribeck'] is True"),
        ("parameters", "effects.mass", True, "unknown effect switch"),
    ],
)
def test_wrong_value_types_rejected_naming_key(tmp_path, section, key, value, word):
    doc = _doc()
    doc[section][key] = value
    msg = _error(_write(tmp_path, doc))  # json.dumps writes NaN / Infinity literals
    assert f"{section}['{key}']" in msg and word in msg, msg


def test_consistent_effect_switch_in_parameters_accepted(tmp_path):
    doc = _doc()
    doc["parameters"]["effects.offset_force"] = False
    m = load_model(_write(tmp_path, doc))
    assert "effects.offset_force" not in m.parameters
    assert m.fmu_parameters()["effects.offset_force"] is False


def test_duplicate_key_and_bad_json_rejected(tmp_path):
    text = '{"name": "a", "name": "b", "effects": {}}'
    assert "duplicate key" in _error(_write(tmp_path, text))
    msg = _error(_write(tmp_path, '{"name": "a",\n "effects": {,}}', "bad.json"))
    assert "line 2" in msg and "column" in msg


def test_with_effect_switches_and_sets_parameters():
    m = paper_model()
    m2 = m.with_effect("offset_force", True, **{"offset.F": 3.5})
    assert m2.effects["offset_force"] is True and m2.parameters["offset.F"] == 3.5
    assert m2.fmu_parameters()["effects.offset_force"] is True
    assert m.effects["offset_force"] is False and m.parameters["offset.F"] == 0.0  # untouched
    m3 = m.with_effect("prerolling", False)
    assert m3.fmu_parameters()["effects.prerolling"] is False
    assert {k: v for k, v in m3.effects.items() if k != "prerolling"} == {
        k: v for k, v in m.effects.items() if k != "prerolling"
    }


@pytest.mark.parametrize(
    "effect,on,params,key",
    [
        ("backlash", True, {}, "effects['backlash']"),
        ("mass", False, {}, "effects['mass']"),
        ("viscous", True, {"friction.sigma": 1.0}, "parameters['friction.sigma']"),
        ("viscous", True, {"friction.sigma2": math.nan}, "parameters['friction.sigma2']"),
        ("viscous", "yes", {}, "effects['viscous']"),
    ],
)
def test_with_effect_validates(effect, on, params, key):
    with pytest.raises(ModelFileError, match=key.replace("[", r"\[").replace("]", r"\]")):
        paper_model().with_effect(effect, on, **params)


def test_save_validates_edited_model(tmp_path):
    m = paper_model()
    m.parameters["m"] = math.inf
    path = tmp_path / "x.json"
    with pytest.raises(ModelFileError, match=r"x\.json: key parameters\['m'\]"):
        save_model(m, path)
    assert not path.exists()


def test_direct_construction_fills_defaults():
    effects = dict(paper_model().effects)
    m = ModelFile("small", effects, {"m": 12.0})
    assert m.parameters["m"] == 12.0 and len(m.parameters) == len(PARAMETER_NAMES)
    assert "m" not in m.defaulted and "Ts" in m.defaulted


INVALID = [  # parameters, the FMU's message (fmu_src/models/plant/params.c)
    ({"m": -16.1}, "m = -16.1 is out of range: allowed (0, inf) kg"),
    (
        {"friction.F_c": 30.0},
        "friction.F_c = 30 exceeds friction.F_s = 26.100000000000001: "
        "allowed friction.F_c in [0, friction.F_s] N",
    ),
    ({"Ts": 0.0}, "Ts = 0 is out of range: allowed (0, inf) s"),
    (
        {"friction.nu[5]": 0.713},
        "friction.nu[1..5] sum to 1.3300000000000001: allowed 1 +- "
        "0.001 (Eq. 12 needs sum(nu) = 1; set friction.nu[5] = 1 - sum "
        "of the others)",
    ),
    (
        {"friction.sigma2": -7135.0},
        "friction.sigma2 = -7135 is out of range: allowed [0, inf) N.s/m",
    ),
]


@pytest.mark.parametrize("params,message", INVALID, ids=[next(iter(p)) for p, _ in INVALID])
def test_invalid_physics_refused_naming_the_file_with_the_fmus_message(tmp_path, params, message):
    doc = _doc()
    doc["parameters"].update(params)
    path = _write(tmp_path, doc)
    assert _error(path) == f"{path}: {message}"
    with pytest.raises(ModelFileError) as err:  # building one in memory, too
        paper_model().with_effect("mass", True, **params)
    assert str(err.value) == f"model 'paper': {message}"


def test_save_refuses_an_edited_model_the_fmu_would_refuse(tmp_path):
    m = paper_model()
    m.parameters["m"] = -16.1  # edited in place, after construction
    with pytest.raises(ModelFileError, match=r"out\.json: m = -16.1 is out of range"):
        save_model(m, tmp_path / "out.json")
    assert not (tmp_path / "out.json").exists()


def test_sum_nu_checked_only_with_prerolling(tmp_path):
    doc = _doc()
    doc["effects"]["prerolling"] = False
    doc["parameters"]["friction.nu[5]"] = 0.713
    assert load_model(_write(tmp_path, doc)).parameters["friction.nu[5]"] == 0.713


def test_every_command_refuses_an_invalid_model_file_with_the_fmus_message(tmp_path, capsys):
    """validate, experiments, identify (--truth) and diagnose: one line naming the file, exit 2."""
    doc = _doc()
    doc["parameters"]["m"] = -16.1
    bad = _write(tmp_path, doc, "bad.json")
    t = np.arange(400) * 5e-4
    run = tmp_path / "run.csv"
    run.write_text(
        "time,u,x\n" + "".join(f"{s:.6f},0.0,{0.15 + 1e-3 * np.sin(20 * s):.9f}\n" for s in t)
    )
    expect = f"{bad}: m = -16.1 is out of range: allowed (0, inf) kg"
    for argv in (
        ["validate", str(run), "--model", str(bad)],
        ["experiments", "--out", str(tmp_path / "exp"), "--model", str(bad)],
        ["identify", str(tmp_path), "--out", str(tmp_path / "id"), "--truth", str(bad)],
        ["diagnose", str(run), "--model", str(bad), "--out", str(tmp_path / "dg")],
    ):
        assert main(argv) == 2, argv
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].endswith(expect), (argv, err)


def test_compliance_round_trip_and_its_integer_sensor_side(tmp_path):
    m = paper_model().with_effect(
        "compliance",
        True,
        **{
            "compliance.m2": 3.5,
            "compliance.f": 87.5,
            "compliance.zeta": 0.12,
            "compliance.sensor_side": 1,
        },
    )
    p = tmp_path / "load.json"
    save_model(m, p)
    back = load_model(p)
    assert back.effects["compliance"] is True and paper_model().effects["compliance"] is False
    for k in ("compliance.m2", "compliance.f", "compliance.zeta"):
        assert back.parameters[k] == m.parameters[k]
    assert back.parameters["compliance.sensor_side"] == 1
    assert isinstance(back.parameters["compliance.sensor_side"], int)
    assert back.fmu_parameters()["effects.compliance"] is True
    doc = json.loads(p.read_text())
    doc["parameters"]["compliance.sensor_side"] = 0.5
    assert "compliance.sensor_side" in _error(_write(tmp_path, doc))
    doc["parameters"]["compliance.sensor_side"] = 0
    doc["parameters"]["compliance.f"] = 500.0  # the FMU's range is 20..200 Hz
    assert "compliance.f = 500 is out of range: allowed [20, 200] Hz" in _error(
        _write(tmp_path, doc)
    )
