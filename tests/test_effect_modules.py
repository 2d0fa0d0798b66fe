"""Each effect of the catalogue is one Python module registered in one list
(:mod:`feeddrive.effects`), and few product files name it (docs/adding-an-effect.md).

The count is :func:`tools.effect_names.naming_files`: a file names effect ``<id>`` when it
holds ``effects.<id>``, the id as a string literal, ``effect_<id>`` / ``EFFECT_<ID>``, or
imports ``feeddrive.effects.<id>``.
"""

from __future__ import annotations

import ast
import importlib
import sys
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

import numpy as np
import pytest

from feeddrive import paper
from feeddrive.diagnose.candidates import CANDIDATES
from feeddrive.effects import (
    EFFECTS,
    Candidate,
    Effect,
    Structure,
    broken_rule,
    effect,
    effect_ids,
    emps_baseline,
    nested,
    nesting,
    paper_scenarios,
    resolve,
    structure_off,
    structure_on,
    switched_off,
)
from feeddrive.experiments import sec3
from feeddrive.identify.pipeline import IdentificationResult
from feeddrive.model_file import paper_model
from feeddrive.physics import GMSParameters, compile
from feeddrive.physics.position_maps import MAP_EFFECTS
from feeddrive.report.identification import effect_rows

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
from effect_names import naming_files, product_files  # noqa: E402

#: Most product files that may name one effect: its XML block, its C file, its Python module
#: and the registry list (an effect without a switch, the mass, has no XML block or C file).
MAX_FILES = 4
NO_SWITCH_FILES = 2


@pytest.fixture(scope="module")
def named() -> dict[str, list[str]]:
    return naming_files(ROOT, effect_ids())


@pytest.mark.parametrize("eid", effect_ids())
def test_few_product_files_name_each_effect(named: dict[str, list[str]], eid: str) -> None:
    files = set(named[eid])
    most = MAX_FILES if effect(eid).switchable else NO_SWITCH_FILES
    assert len(files) <= most, (
        f"{eid} is named in {len(files)} product files (allowed {most}): {sorted(files)}"
    )
    module = f"python/feeddrive/effects/{eid}.py"
    assert module in files and "python/feeddrive/effects/__init__.py" in files


def test_the_count_sees_every_way_of_naming(tmp_path: Path) -> None:
    (tmp_path / "python/feeddrive/effects").mkdir(parents=True)
    (tmp_path / "fmu_src").mkdir()
    files = {
        "modelDescription.xml": '<ScalarVariable name="effects.stribeck"/>',
        "fmu_src/friction.c": 'static const char *n = "stribeck";',
        "fmu_src/table.h": "EFFECT_STRIBECK,",
        "python/feeddrive/a.py": 'IDS = ["viscous", "stribeck"]\n',
        "python/feeddrive/b.py": "from feeddrive.effects import stribeck\n",
        "python/feeddrive/effects/c.py": "from . import stribeck as s\n",
        "python/feeddrive/d.py": "effect_stribeck = 1\n",
        "python/feeddrive/e.py": '"""The Stribeck curve; "stribeck" in a docstring."""\n'
        'name = f"stribeck_{1}"\n',
        "python/feeddrive/f.py": 'x = {"effects.stribeck": True}\n',
    }
    for rel, text in files.items():
        (tmp_path / rel).write_text(text)
    assert len(product_files(tmp_path)) == len(files)
    got = naming_files(tmp_path, ["stribeck", "viscous"])
    assert sorted(got["stribeck"]) == sorted(set(files) - {"python/feeddrive/e.py"})
    assert got["viscous"] == ["python/feeddrive/a.py"]


def test_every_effect_has_its_module_and_registers_once() -> None:
    assert len({e.id for e in EFFECTS}) == len(EFFECTS)
    for e in EFFECTS:
        mod = importlib.import_module(f"feeddrive.effects.{e.id}")
        assert mod.EFFECT is e and effect(e.id) is e
    with pytest.raises(KeyError, match="not an effect of the catalogue"):
        effect("backlash")


def _xml_variables() -> dict[str, ElementTree.Element]:
    root = ElementTree.parse(ROOT / "modelDescription.xml").getroot()
    return {v.attrib["name"]: v for v in root.iter("ScalarVariable")}


def test_registry_and_model_description_agree() -> None:
    xml = _xml_variables()
    declared = {n: v for n, v in xml.items() if n.startswith("effects.")}
    assert set(declared) == {e.switch for e in EFFECTS if e.switch is not None}
    for e in EFFECTS:
        if e.switch is None:
            assert not any(p.name in declared for p in e.parameters)
            continue
        v = declared[e.switch]
        boolean = v.find("Boolean")
        assert v.attrib["causality"] == "parameter" and boolean is not None, e.id
        assert (boolean.attrib["start"] == "true") == e.in_paper, e.id
        assert e.description in v.attrib["description"], (e.id, v.attrib["description"])
    for e in EFFECTS:
        for p in e.parameters:
            name = p.name.replace("[j]", "[1]")
            assert name in xml and xml[name].attrib["causality"] == "parameter", (
                f"{e.id}: parameter {p.name} is no FMU parameter"
            )


def test_every_reference_of_the_registry_resolves() -> None:
    for e in EFFECTS:
        for ref in (e.physics, e.identification.fit, e.candidate.builder):
            if ref:
                assert resolve(ref) is not None, (e.id, ref)
        assert CANDIDATES[e.id] is resolve(e.candidate.builder)
    with pytest.raises(ValueError, match=r"allowed 'package\.module:attribute'"):
        resolve("feeddrive.physics")


def test_lists_of_effects_come_from_the_registry() -> None:
    assert paper.EFFECT_IDS == [e.id for e in EFFECTS] == list(CANDIDATES)
    assert paper.SWITCHABLE_EFFECTS == [e.id for e in EFFECTS if e.switch]
    assert paper.BEYOND_PAPER == tuple(e.id for e in EFFECTS if not e.in_paper)
    assert set(MAP_EFFECTS) == {"cogging", "ripple"}
    assert {e.id for e in EFFECTS if e.position_map} == set(sum(MAP_EFFECTS.values(), ()))
    with pytest.raises(ValueError, match=r"allowed 'effects\.x' or None"):
        Effect(
            "x", "effects.y", False, "", (), "", EFFECTS[0].identification, EFFECTS[0].candidate, ()
        )


#: What an effect module may import besides the shared modules of :mod:`feeddrive.effects`.
EFFECT_MODULE_LIBRARIES = {"numpy", "scipy", "dataclasses", "typing", "collections"}


def test_effect_modules_import_only_the_effect_type() -> None:
    """The registry sits below every other module: an effect module imports nothing of the
    package but the shared modules of :mod:`feeddrive.effects` (:mod:`~feeddrive.effects.effect`,
    :mod:`~feeddrive.effects.candidate`, :mod:`~feeddrive.effects.steps`), no other effect
    module, and besides only numpy, scipy and the standard library's types."""
    pkg = ROOT / "python/feeddrive/effects"
    shared = {"effect", "candidate", "steps"}
    for f in sorted(pkg.glob("*.py")):
        if f.name in ("__init__.py", "effect.py", "candidate.py", "steps.py"):
            continue
        tree = ast.parse(f.read_text())
        relative = [n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.level]
        absolute = [
            n.module
            for n in ast.walk(tree)
            if isinstance(n, ast.ImportFrom) and not n.level and n.module != "__future__"
        ] + [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
        assert "effect" in relative and set(relative) <= shared, f"{f.name} imports {relative}"
        assert {str(m).split(".")[0] for m in absolute} <= EFFECT_MODULE_LIBRARIES, (
            f"{f.name} imports {absolute}"
        )


@pytest.mark.parametrize("e", [e for e in EFFECTS if e.off], ids=lambda e: e.id)
def test_off_rules_are_the_physics_of_the_switch(e: Effect) -> None:
    """An effect switched off compiles to the plant its ``off`` rule's values make with it on."""
    v: dict[str, Any] = {
        **paper.paper_parameters(),
        "asymmetry.dF": 1.5,
        "asymmetry.dsigma2": 20.0,
        "offset.F": 3.0,
    }
    v.update(
        {s.switch: True for s in EFFECTS if s.switch and s.switch != "effects.position_friction"}
    )
    assert e.switch is not None
    off_v = {**v, e.switch: False}
    ruled_v = {**switched_off(off_v, [e]), e.switch: True}
    assert GMSParameters.from_params(off_v) == GMSParameters.from_params(ruled_v)
    if not all(np.isfinite(float(x)) for x in ruled_v.values()):
        return  # C = inf: no FMU value, the GMS says all
    off, ruled = compile(off_v), compile(ruled_v)
    assert off.friction == ruled.friction and off.F_offset == ruled.F_offset
    x = np.linspace(-0.01, 0.31, 97)
    np.testing.assert_array_equal(off.K_f(x), ruled.K_f(x))
    np.testing.assert_array_equal(off.F_cg(x), ruled.F_cg(x))


def test_the_catalogue_page_lists_the_registry() -> None:
    """docs/effects.md's table has one row per effect of the registry, in its order."""
    rows = [
        line.split("|")[1].strip().strip("`")
        for line in (ROOT / "docs/effects.md").read_text().splitlines()
        if line.startswith("| `")
    ]
    assert rows == effect_ids()


def test_the_identification_report_has_a_row_per_effect() -> None:
    res = IdentificationResult(model=paper_model(), groups={})
    res.mass = object()
    rows = {r["effect"]: r for r in effect_rows(res)}
    assert list(rows) == effect_ids()
    assert (
        rows["mass"]["step"] == "mass: fitted"
        and rows["stribeck"]["step"] == "stribeck: not fitted"
    )
    assert rows["offset_force"]["on"] == "no" and rows["viscous"]["step"] == "no step of its own"


def test_every_plant_structure_is_selected_by_one_switch() -> None:
    """Each structural option of the compiled plant belongs to one switchable effect; its
    switch (missing: the FMU's default) decides it in the compiled types."""
    for s in Structure:
        owners = [e for e in EFFECTS if e.structure is s]
        assert len(owners) == 1 and owners[0].switch is not None, s
        assert structure_on({}, s) is owners[0].in_paper
        assert structure_off(s) == {owners[0].switch: False}
    on = compile({e.switch: True for e in EFFECTS if e.structure and e.switch})
    off = compile({k: v for s in Structure for k, v in structure_off(s).items()})
    assert on.prerolling and on.current.dynamics and on.compliance.on and on.friction.profile
    assert not (off.prerolling or off.current.dynamics or off.compliance.on)
    assert off.friction.profile is None
    assert off.current.polynomials()[1].tolist() == [1.0]


def test_effect_rules_are_the_fmu_rules_in_table_order() -> None:
    """The effects' rules pass the paper's parameters and refuse in the FMU's order: every
    compile rule (the asymmetry's levels) before any check rule (N, sum(nu), the profile)."""
    v = paper.paper_parameters()
    assert broken_rule(v) is None
    bad = {
        **v,
        "effects.asymmetric_friction": True,
        "asymmetry.dF": -50.0,
        "friction.N": 3.5,
        "friction_profile.n": 3.5,
    }
    assert (broken_rule(bad) or "").startswith("asymmetry.dF = -50 makes the friction level")
    bad["asymmetry.dF"] = 0.0
    assert broken_rule(bad) == "friction.N = 3.5 is not an integer: allowed 1..10"
    bad["friction.N"] = 3.0
    nu = sum(v[f"friction.nu[{j}]"] for j in (1, 2, 3))
    assert broken_rule(bad) == (
        f"friction.nu[1..3] sum to {nu:.17g}: allowed 1 +- 0.001 (Eq. 12 needs sum(nu) = 1; "
        "set friction.nu[3] = 1 - sum of the others)"
    )
    bad["effects.prerolling"] = False
    assert broken_rule(bad) == "friction_profile.n = 3.5 is not an integer: allowed 2..16"


def test_the_paper_scenarios_switch_paper_effects_off() -> None:
    """Sec. 3's variants: the full model, then one per effect that declares a scenario."""
    scenarios = paper_scenarios()
    assert list(scenarios) == ["without aperiodic cogging", "static friction instead of GMS"]
    for label, change in scenarios.items():
        (e,) = [e for e in EFFECTS if e.scenario == label]
        assert e.in_paper and change == {e.switch: False}
    assert sec3.VARIANTS == {"full model": {}, **scenarios}


def test_candidate_nesting_and_the_emps_baseline_are_registry_data() -> None:
    """A load on a spring reduces to a change of the mass (its candidate's ``limit`` is the
    mass's parameter); the EMPS rigid baseline is mass, viscous friction and an offset."""
    assert nesting() == {"compliance": "mass"}
    assert emps_baseline() == ["viscous", "mass", "offset_force"]
    odd = Effect(
        "x", None, False, "", (), "", EFFECTS[0].identification, Candidate("", (), "", ("q",)), ()
    )
    with pytest.raises(ValueError, match="candidate limit"):
        nested([*EFFECTS, odd])
