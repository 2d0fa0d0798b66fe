"""The FMU carries its sources: `fmpy compile` rebuilds the binary and it simulates the same."""

from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu


def test_fmpy_compile_rebuilds_from_sources(fmu_version, tmp_path):
    """Both versions: FMI 2.0 from <SourceFiles>, FMI 3.0 from sources/buildDescription.xml."""
    fmu_path, _ = fmu_version
    if shutil.which("cmake") is None:
        pytest.skip("cmake is not installed: fmpy compile needs it")
    copy = tmp_path / fmu_path.name
    shutil.copy(fmu_path, copy)
    names = zipfile.ZipFile(copy).namelist()
    assert "sources/model_vars.h" in names and "sources/plant.c" in names
    fmpy_cli = Path(sys.executable).with_name("fmpy")
    p = subprocess.run(
        [str(fmpy_cli), "compile", str(copy)], capture_output=True, text=True, timeout=600
    )
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    sv = {"u": 0.4, "friction.C": 10.8}
    a = simulate_fmu(str(fmu_path), stop_time=0.2, start_values=sv, output=["x", "F_friction"])
    b = simulate_fmu(str(copy), stop_time=0.2, start_values=sv, output=["x", "F_friction"])
    assert np.allclose(a["x"], b["x"], rtol=0, atol=1e-12)
    assert np.allclose(a["F_friction"], b["F_friction"], rtol=0, atol=1e-9)


def _plant_sources(root_dir: Path) -> list[Path]:
    """The plant's C files: fmu_src/ less the controller's."""
    return [p for p in (root_dir / "fmu_src").rglob("*.c") if "controller" not in p.parts]


def test_source_files_listed_in_the_model_description_are_the_sources(fmu_path):
    """modelDescription.xml's <SourceFiles> (ME and CS) name exactly the C files of fmu_src/
    but the FMI 3.0 glue (fmi3*.c) plus the generated model_vars.c, and the FMU ships each of
    them in sources/."""
    import xml.etree.ElementTree as ET

    root_dir = Path(__file__).resolve().parents[1]
    md = ET.parse(root_dir / "modelDescription.xml").getroot()
    expected = {p.name for p in _plant_sources(root_dir) if not p.name.startswith("fmi3")} | {
        "model_vars.c"
    }
    shipped = set(zipfile.ZipFile(fmu_path).namelist())
    for kind in ("ModelExchange", "CoSimulation"):
        listed = {f.get("name") for f in md.find(kind).find("SourceFiles").findall("File")}
        assert listed == expected, kind
        assert {f"sources/{n}" for n in listed} <= shipped


def test_fmi3_build_description_lists_every_source(fmu3_path):
    """sources/buildDescription.xml of the FMI 3.0 FMU names every C file of fmu_src/ and the
    generated model_vars.c / model_vars3.c, and the FMU ships each of them."""
    import xml.etree.ElementTree as ET

    root_dir = Path(__file__).resolve().parents[1]
    z = zipfile.ZipFile(fmu3_path)
    bd = ET.fromstring(z.read("sources/buildDescription.xml"))
    listed = {f.get("name") for f in bd.iter("SourceFile")}
    assert listed == {p.name for p in _plant_sources(root_dir)} | {"model_vars.c", "model_vars3.c"}
    assert {f"sources/{n}" for n in listed} <= set(z.namelist())
