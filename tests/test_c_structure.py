"""Structure of the C sources (fmu_src/): every FMI entry point is admitted by the one
allowed-state table, the FMI glue knows nothing of friction, and no function is long."""
from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "fmu_src"
FMI = SRC / "fmi"
GLUE = sorted(FMI.glob("*.c")) + sorted(FMI.glob("*.h"))
MAX_LINES = 60
# identifiers of the friction models (plant.h, friction_gms.c, friction_static.c)
FRICTION = re.compile(r"\b(stuck|st_stuck|st_dir|active|prerolling|lag|nu|sigma2|Fs|Fc|Vs|"
                      r"PLANT_NE_MAX|PLANT_IF|gms_\w+|static_\w+|friction_\w+|VRA_friction_\w+)\b")
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
            body = text[m.end(): text.index("\n}", m.end())]
            assert f"FMU_ENTER({comp}, {name})" in body, f"{path.name}: {name} does not start with FMU_ENTER"
            assert "fmu_enter(" not in body, f"{path.name}: {name} calls fmu_enter with its own mask"
    assert len(defined) >= 40, sorted(defined)
    assert table == defined, f"table without function: {table - defined}; function without entry: {defined - table}"


def test_fmi_glue_knows_nothing_of_friction() -> None:
    for path in GLUE:
        hits = sorted(set(FRICTION.findall(_code(path))))
        assert not hits, f"{path.name} uses friction internals: {hits}"


def test_no_function_longer_than_sixty_lines() -> None:
    long = [f"{p.name}:{line} {name} ({n} lines)" for p in sorted(SRC.rglob("*.c"))
            for name, line, n in _functions(p.read_text(encoding="utf-8")) if n > MAX_LINES]
    assert not long, long
