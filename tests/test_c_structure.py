"""Structure of the C sources (fmu_src/): every FMI entry point is admitted by the one
allowed-state table, the FMI glue knows nothing of friction, its files call each other in one
direction only, each model's capabilities agree with its model descriptions, and no function
is long."""

from __future__ import annotations

import re
import zipfile
from pathlib import Path
from xml.etree import ElementTree as ET

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "fmu_src"
FMI = SRC / "fmi"
GLUE = sorted(FMI.glob("*.c")) + sorted(FMI.glob("*.h"))
MAX_LINES = 60
# identifiers of the friction models (plant.h, friction_gms.c, friction_static.c)
FRICTION = re.compile(
    r"\b(stuck|st_stuck|st_dir|active|prerolling|lag|nu|sigma2|Fs|Fc|Vs|"
    r"PLANT_NE_MAX|PLANT_IF|gms_\w+|static_\w+|friction_\w+|VRA_friction_\w+)\b"
)
ENTRY = re.compile(r"^(?:fmi2Status|void|fmi2Component)\s+(fmi2\w+)\((fmi2Component)\s+(\w+)", re.M)


def _code(path: Path) -> str:
    """The source without comments and string literals."""
    text = re.sub(r"/\*.*?\*/", " ", path.read_text(encoding="utf-8"), flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    return re.sub(r'"(?:[^"\\\n]|\\.)*"', '""', text)


def _functions(text: str):
    """(name, first line, number of lines) of every function definition at file scope."""
    for m in re.finditer(r"^[A-Za-z_][\w \*]*?\b(\w+)\s*\([^;{]*?\)\s*\{", text, re.M | re.S):
        depth, i = 0, m.end() - 1
        while True:
            depth += {"{": 1, "}": -1}.get(text[i], 0)
            if depth == 0:
                break
            i += 1
        first = text.count("\n", 0, m.start()) + 1
        yield m.group(1), first, text.count("\n", m.start(), i) + 1


def test_every_fmi_entry_point_enters_through_the_table() -> None:
    table = set(re.findall(r"#define ALLOW_(fmi2\w+)\s", (FMI / "allowed.h").read_text()))
    defined = set()
    for path in FMI.glob("fmi2*.c"):
        text = _code(path)
        for m in ENTRY.finditer(text):
            name, comp = m.group(1), m.group(3)
            defined.add(name)
            body = text[m.end() : text.index("\n}", m.end())]
            assert f"FMU_ENTER({comp}, {name})" in body, (
                f"{path.name}: {name} does not start with FMU_ENTER"
            )
            assert "fmu_enter(" not in body, (
                f"{path.name}: {name} calls fmu_enter with its own mask"
            )
    assert len(defined) >= 40, sorted(defined)
    assert table == defined, (
        f"table without function: {table - defined}; function without entry: {defined - table}"
    )


def test_fmi_glue_knows_nothing_of_friction() -> None:
    for path in GLUE:
        hits = sorted(set(FRICTION.findall(_code(path))))
        assert not hits, f"{path.name} uses friction internals: {hits}"


def test_no_function_longer_than_sixty_lines() -> None:
    long = [
        f"{p.name}:{line} {name} ({n} lines)"
        for p in sorted(SRC.rglob("*.c"))
        for name, line, n in _functions(p.read_text(encoding="utf-8"))
        if n > MAX_LINES
    ]
    assert not long, long


def test_glue_files_call_each_other_in_one_direction() -> None:
    """The graph "file A calls a function defined in file B" over fmu_src/fmi/*.c has no cycle."""
    code = {p.name: _code(p) for p in sorted(FMI.glob("*.c"))}
    defined = {name: {f for f, _, _ in _functions(text)} for name, text in code.items()}
    owner = {f: name for name, fs in defined.items() for f in fs}
    calls = {
        name: {
            owner[f] for f in set(re.findall(r"\b(\w+)\s*\(", text)) if owner.get(f, name) != name
        }
        for name, text in code.items()
    }
    assert sum(len(v) for v in calls.values()) >= 10, calls
    done: set[str] = set()

    def visit(name: str, path: list[str]) -> None:
        assert name not in path, f"file cycle: {' -> '.join(path + [name])}"
        if name not in done:
            for other in sorted(calls[name]):
                visit(other, path + [name])
            done.add(name)

    for name in sorted(calls):
        visit(name, [])


CAPS = {"ME": 1, "CS": 2, "STATE": 4, "CONFIG": 8, "EARLY_RETURN": 16, "CLOCKS": 32}


def _caps(model: str) -> set[str]:
    text = (SRC / "models" / model / "model_data.h").read_text(encoding="utf-8")
    line = re.search(r"#define MODEL_CAPS \(([^)]*)\)", text).group(1)
    return {w.removeprefix("MODEL_CAN_") for w in re.findall(r"MODEL_CAN_\w+", line)}


def _xml3(fmu: Path) -> ET.Element:
    return ET.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))


def test_model_capabilities_agree_with_the_model_descriptions(fmu3_path: Path) -> None:
    """MODEL_CAPS of each model (what the glue offers and refuses for it) says what its FMI 2.0
    and FMI 3.0 model descriptions declare: the interfaces, FMU states, a structural parameter,
    early return and clocks."""
    fmus = {
        "plant": (ROOT / "modelDescription.xml", fmu3_path),
        "controller": (
            SRC / "models" / "controller" / "modelDescription.xml",
            fmu3_path.with_name("DriveController3.fmu"),
        ),
    }
    for model, (xml2, fmu3) in fmus.items():
        md2, md3 = ET.parse(xml2).getroot(), _xml3(fmu3)
        cs2, cs3 = md2.find("CoSimulation"), md3.find("CoSimulation")
        declared = {
            "ME": md2.find("ModelExchange") is not None and md3.find("ModelExchange") is not None,
            "CS": cs2 is not None and cs3 is not None,
            "STATE": cs2.get("canGetAndSetFMUstate") == "true"
            and cs3.get("canGetAndSetFMUState") == "true",
            "CONFIG": any(
                v.get("causality") == "structuralParameter" for v in md3.find("ModelVariables")
            ),
            "EARLY_RETURN": cs3.get("mightReturnEarlyFromDoStep") == "true",
            "CLOCKS": md3.find("ModelVariables").find("Clock") is not None,
        }
        assert _caps(model) == {k for k, v in declared.items() if v}, (model, declared)
