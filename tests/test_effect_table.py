"""The plant's effect table in C (fmu_src/physics/effect.h): its list of effects is generated from
the `effects.*` switches of modelDescription.xml, each effect's entry is defined in one C file of
fmu_src/physics/ and that file alone reads the switch; the entries compile and check in the
table's order, so with several rules broken the FMU names the same first one as the Python twin."""

from __future__ import annotations

import importlib.util
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from feeddrive.fmu import FMUError, Plant
from feeddrive.physics import ParameterError, compile

REPO = Path(__file__).resolve().parents[1]
FMU_SRC = REPO / "fmu_src"


def _gen_vars():
    spec = importlib.util.spec_from_file_location(
        "gen_vars", FMU_SRC / "generators" / "gen_vars.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _switches() -> list[str]:
    root = ET.parse(REPO / "modelDescription.xml").getroot()
    return [
        sv.get("name").split(".", 1)[1]
        for sv in root.find("ModelVariables")
        if sv.get("name").startswith("effects.")
    ]


def test_generated_list_is_the_xml_switches_in_order(tmp_path):
    _gen_vars().main(str(REPO / "modelDescription.xml"), str(tmp_path))
    text = (tmp_path / "model_effects.h").read_text()
    ids = re.findall(r"^\s+X\((\w+)\)", text, re.M)
    assert ids == _switches()
    assert f"#define MODEL_NEFFECTS {len(ids)}" in text
    assert len(ids) == 13


def test_each_entry_in_one_file_that_alone_reads_its_switch():
    sources = {p: p.read_text() for p in FMU_SRC.rglob("*.[ch]")}
    for eid in _switches():
        defining = [
            p
            for p, t in sources.items()
            if re.search(rf'const effect_t effect_{eid} = \{{\s*"{eid}", VR_effects_{eid},', t)
        ]
        assert len(defining) == 1, (eid, defining)
        assert defining[0].parent == FMU_SRC / "physics", eid
        readers = [p for p, t in sources.items() if f"VR_effects_{eid}" in t]
        assert readers == defining, (eid, readers)


def _fmu_first(plant: Plant, values: dict) -> str:
    plant.parameters = dict(values)
    with pytest.raises(FMUError):
        plant.start()
    return plant.messages[-1]


def _py_first(values: dict) -> str:
    with pytest.raises(ParameterError) as e:
        compile(values)
    return str(e.value)


#: two rules broken at once, of different effects; the message expected first (table order:
#: compile of every entry, then the rules of combination)
PAIRS = [
    (
        {"current.a[1]": 1.5, "current.a[2]": -0.5, "stroke.x_min": 0.2, "stroke.x_max": 0.1},
        "current.a[1..5] sum",
    ),
    ({"stroke.x_min": 0.2, "stroke.x_max": 0.1, "friction.F_c": 30.0}, "stroke.x_max = "),
    (
        {"friction.F_c": 30.0, "effects.asymmetric_friction": True, "asymmetry.dF": -40.0},
        "friction.F_c = 30",
    ),
    (
        {"effects.asymmetric_friction": True, "asymmetry.dF": -30.0, "friction.nu[5]": 0.713},
        "asymmetry.dF = -30",
    ),
    (
        {
            "effects.asymmetric_friction": True,
            "asymmetry.dF": -30.0,
            "friction_profile.x_start": 0.2,
            "friction_profile.x_end": 0.2,
        },
        "asymmetry.dF = -30",
    ),
    (
        {"friction.nu[5]": 0.713, "friction_profile.x_start": 0.2, "friction_profile.x_end": 0.2},
        "friction.nu[1..5]",
    ),
    (
        {
            "current.a[1]": 1.5,
            "current.a[2]": -0.5,
            "friction_profile.x_start": 0.2,
            "friction_profile.x_end": 0.2,
        },
        "current.a[1..5] sum",
    ),
]


@pytest.fixture(scope="module")
def plant(fmu_path):
    with Plant(path=fmu_path) as p:
        yield p


@pytest.mark.parametrize(
    "values,first", PAIRS, ids=[p[1].split(" ")[0] + f"-{i}" for i, p in enumerate(PAIRS)]
)
def test_first_of_several_broken_rules_agrees(plant, values, first):
    got = _fmu_first(plant, values)
    assert got.startswith(first), got
    assert got == _py_first(values)
