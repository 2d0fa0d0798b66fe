"""The compile-time checks of fmu_src/models/plant/params.c: the plant's counts of continuous states and event
indicators must equal those of the header generated from modelDescription.xml (gen_vars.py), or
the FMU does not build, and the failure names the check."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "fmu_src"
PLANT_DIRS = ("fmi", "models/plant", "physics", "solvers")
XML = ROOT / "modelDescription.xml"
FLAGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-fsyntax-only"]


def _compile_params(tmp_path: Path, xml_text: str) -> subprocess.CompletedProcess[str]:
    """Generate model_vars.h from xml_text and compile params.c against it."""
    cc = shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
    assert cc is not None, "no C compiler on PATH"
    xml = tmp_path / "modelDescription.xml"
    xml.write_text(xml_text, encoding="utf-8")
    gen = tmp_path / "gen"
    subprocess.run(
        [sys.executable, str(SRC / "generators" / "gen_vars.py"), str(xml), str(gen)],
        check=True,
        timeout=60,
    )
    return subprocess.run(
        [
            cc,
            *FLAGS,
            *(f"-I{SRC / d}" for d in PLANT_DIRS),
            f"-I{gen}",
            str(SRC / "models" / "plant" / "params.c"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_params_compiles_against_the_model_description(tmp_path: Path) -> None:
    proc = _compile_params(tmp_path, XML.read_text(encoding="utf-8"))
    assert proc.returncode == 0, proc.stderr


def _one_state_less(text: str) -> str:
    der = re.search(r"<Derivatives>.*?</Derivatives>", text, re.S)
    assert der is not None
    block = der.group(0)
    last = list(re.finditer(r"\s*<Unknown [^>]*/>", block))[-1]
    return text.replace(block, block[: last.start()] + block[last.end() :])


def _one_indicator_less(text: str) -> str:
    n = int(re.search(r'numberOfEventIndicators="(\d+)"', text).group(1))
    return text.replace(f'numberOfEventIndicators="{n}"', f'numberOfEventIndicators="{n - 1}"')


@pytest.mark.parametrize(
    "edit, check",
    [
        (_one_state_less, "compile_check_continuous_states_match_xml"),
        (_one_indicator_less, "compile_check_event_indicators_match_xml"),
    ],
)
def test_count_mismatch_fails_the_build(tmp_path: Path, edit, check: str) -> None:
    proc = _compile_params(tmp_path, edit(XML.read_text(encoding="utf-8")))
    assert proc.returncode != 0, "params.c compiled against a model description with other counts"
    assert check in proc.stderr, proc.stderr
