"""One source of truth: modelDescription.xml, the generated C table and the paper agree."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from feeddrive.fmu import Plant

REPO = Path(__file__).resolve().parents[1]
XML = REPO / "modelDescription.xml"
GEN = REPO / "build" / "gen"


def _ident(name: str) -> str:
    """C identifier of a variable name: friction.F[1] -> friction_F_1 (the generator's rule)."""
    return re.sub(r"_+", "_", re.sub(r"[^A-Za-z0-9]", "_", name)).strip("_")


def _xml_vars() -> list[dict]:
    root = ET.parse(XML).getroot()
    out = []
    for sv in root.find("ModelVariables").findall("ScalarVariable"):
        t = sv[0]
        out.append(
            {
                "name": sv.get("name"),
                "vr": int(sv.get("valueReference")),
                "type": t.tag,
                "causality": sv.get("causality", "local"),
                "variability": sv.get("variability", "continuous"),
                "start": t.get("start"),
                "unit": t.get("unit", ""),
                "nominal": float(t.get("nominal", "1")),
            }
        )
    return out


def _value(text: str, typ: str) -> float:
    if typ == "Boolean":
        return 1.0 if text == "true" else 0.0
    return float(text)


@pytest.fixture(scope="module")
def gen_files(fmu_path: Path) -> tuple[str, str]:
    h, c = GEN / "model_vars.h", GEN / "model_vars.c"
    assert h.is_file() and c.is_file(), "build/gen/model_vars.{h,c} missing: run `make fmu`"
    return h.read_text(), c.read_text()


def test_header_value_references_match_xml(gen_files: tuple[str, str]) -> None:
    h, _ = gen_files
    defines = {m.group(1): int(m.group(2)) for m in re.finditer(r"#define VR_(\w+) (\d+)u", h)}
    xv = _xml_vars()
    assert len(defines) == len(xv)
    for v in xv:
        assert defines.get(_ident(v["name"])) == v["vr"], v["name"]
    assert int(re.search(r"#define MODEL_NVARS (\d+)", h).group(1)) == len(xv)
    # the indexed groups (friction.nu[1..10], cogging.a[1..8], ...) address the same VRs
    by_name = {v["name"]: v["vr"] for v in xv}
    groups = re.findall(r"VRA_(\w+)\[(\d+)\] = \{([^}]*)\}", h)
    assert groups, "no VRA_ arrays in model_vars.h"
    for ident, size, body in groups:
        vals = [int(s.strip().rstrip("u")) for s in body.split(",")]
        assert len(vals) == int(size)
        members = {
            n: vr
            for n, vr in by_name.items()
            if re.fullmatch(r"(.*)\[(\d+)\]", n)
            and not n.startswith("der(")
            and _ident(n.rsplit("[", 1)[0]) == ident
        }
        assert members, ident
        for n, vr in members.items():
            assert vals[int(n.rsplit("[", 1)[1][:-1])] == vr, n


ROW = re.compile(
    r'\{(\d+)u, "([^"]+)", \'(\w)\', \'(\w)\', \'(\w)\', ([^,]+), (\d), ([^,]+), ([^,]+), '
    r'"([^"]*)", ([^}]+)\}'
)


def test_c_table_rows_match_xml(gen_files: tuple[str, str]) -> None:
    _, c = gen_files
    rows = {m.group(2): m for m in ROW.finditer(c)}
    xv = _xml_vars()
    assert len(rows) == len(xv)
    for v in xv:
        r = rows[v["name"]]
        assert int(r.group(1)) == v["vr"], v["name"]
        assert r.group(3) == v["type"][0], v["name"]
        caus = "c" if v["causality"] == "calculatedParameter" else v["causality"][0]
        assert r.group(4) == caus, v["name"]
        assert r.group(5) == v["variability"][0], v["name"]
        assert r.group(10) == v["unit"], v["name"]
        assert float(r.group(11)) == v["nominal"], v["name"]
        if v["start"] is None:
            assert r.group(7) == "0", v["name"]
        else:
            assert r.group(7) == "1", v["name"]
            assert float(r.group(6)) == _value(v["start"], v["type"]), v["name"]


def _xml_parameters() -> dict[str, float]:
    return {
        v["name"]: _value(v["start"], v["type"])
        for v in _xml_vars()
        if v["causality"] == "parameter"
    }


def test_xml_defaults_are_the_paper_parameters(paper: dict) -> None:
    xp = _xml_parameters()
    missing = sorted(set(paper) - set(xp))
    assert not missing, f"paper parameters without an FMU variable: {missing}"
    extra = sorted(set(xp) - set(paper))
    assert extra == ["solver.fast", "solver.tol"], (
        f"FMU parameters not in paper_parameters(): {extra}"
    )
    for name, value in paper.items():
        assert math.isclose(xp[name], float(value), rel_tol=1e-12, abs_tol=1e-300), (
            f"{name}: XML start {xp[name]!r}, paper {value!r}"
        )


def test_fmu_binary_holds_the_paper_parameters(fmu_path: Path, paper: dict) -> None:
    """The compiled table (what the .so really uses) equals paper_parameters() too."""
    with Plant(interface="me", path=fmu_path) as plant:
        plant.start()
        got = plant.get(list(paper))
    for name, value in paper.items():
        assert math.isclose(float(got[name]), float(value), rel_tol=1e-12, abs_tol=1e-300), name


def test_state_nominals_come_from_the_model_description(fmu_path):
    """fmi2GetNominalsOfContinuousStates reports the XML's nominal attributes of the states
    (the co-simulation solver scales its absolute tolerances by the same numbers)."""
    import ctypes

    from fmpy import read_model_description

    from feeddrive.fmu import Plant

    md = read_model_description(str(fmu_path))
    states = [d.variable.derivative for d in md.derivatives]
    expected = [float(s.nominal) if s.nominal is not None else 1.0 for s in states]
    with Plant(interface="me", path=fmu_path) as p:
        p.start()
        buf = (ctypes.c_double * len(expected))()
        p.fmu.getNominalsOfContinuousStates(buf, len(expected))
        assert list(buf) == expected
    assert expected[:2] == [1e-3, 1e-3] and expected[2:12] == [1.0] * 10
    assert expected[12:] == [1e-5, 1e-3]  # compliance.dx [m], compliance.dv [m/s]


def test_no_xml_comment_inside_model_variables() -> None:
    """Some importers (fmipp 2.1) count every child of ModelVariables, comments included, as a
    ScalarVariable: the list holds ScalarVariable elements only."""
    text = XML.read_text()
    block = text[text.index("<ModelVariables>") : text.index("</ModelVariables>")]
    assert "<!--" not in block
    children = [c.tag for c in ET.fromstring(text).find("ModelVariables")]
    assert children and set(children) == {"ScalarVariable"}
