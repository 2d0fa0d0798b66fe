"""`feeddrive fmu`: a model file as its own plant FMU (FMI 2.0 and 3.0) and an SSP parameter set.

The exported FMU set no parameter runs the importer scenario (tests/importer_scenario.py: 2 s
open loop, stick and slip at every reversal) exactly as the source FMU with the model's
parameters set: the same binary with the same values, so bit for bit (``np.array_equal``), in
fmpy (both versions) and in FMI++ (fmipp, FMI 2.0 co-simulation, its own process).  The model
is not the paper's: another mass, an offset force, three GMS elements, another Stribeck speed,
the aperiodic ripple off; without the start values the FMU runs the paper's drive and the
positions differ by millimetres.
"""

from __future__ import annotations

import json
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.ssp.ssd import read_ssv
from fmpy.validation import validate_fmu

from feeddrive import cli
from feeddrive.export_fmu import START_VALUES, export_fmu, literal
from feeddrive.fmu import Plant
from feeddrive.harness.simulate import simulate_open_loop
from feeddrive.model_file import load_model, paper_model, save_model
from importer_scenario import COLUMNS, X0, grid, u_input

HERE = Path(__file__).resolve().parent

MACHINE = {
    "m": 23.75,
    "offset.F": -2.125,
    "friction.N": 3,
    "friction.V_s": 0.0047,
    "friction.nu[1]": 0.25,
    "friction.nu[2]": 0.35,
    "friction.nu[3]": 0.4,
    "friction.k[1]": 8.0e5,
    "friction.k[2]": 2.5e5,
    "friction.k[3]": 6.0e4,
    "friction.F_s": 31.5,
    "friction.F_c": 24.0,
}


@pytest.fixture(scope="module")
def machine_file(tmp_path_factory) -> Path:
    model = (
        paper_model()
        .with_effect("offset_force", True, **MACHINE)
        .with_effect("ripple_aperiodic", False)
    )
    model.name, model.description = "test machine", "a drive that is not the paper's"
    path = tmp_path_factory.mktemp("model") / "machine.json"
    save_model(model, path)
    return path


@pytest.fixture(scope="module")
def exported(machine_file, fmu2_path, fmu3_path, tmp_path_factory) -> dict[int, Path]:
    out = tmp_path_factory.mktemp("export")
    model = load_model(machine_file)
    return {
        fmi: export_fmu(
            model, out / f"Machine{fmi}.fmu", fmi, model_path=machine_file, source=src
        ).fmu
        for fmi, src in ((2, fmu2_path), (3, fmu3_path))
    }


def _scenario(path: Path, parameters: dict | None = None) -> dict[str, np.ndarray]:
    t = grid()
    with Plant(parameters, interface="cs", tolerance=1e-6, path=path) as p:
        r = simulate_open_loop(p, t, u_input(t), start_values={"x": X0, "v": 0.0})
        return {c: np.asarray(r[c]) for c in COLUMNS}


@pytest.mark.parametrize("fmi", [2, 3])
def test_fmpy_validate_clean(exported, fmi) -> None:
    problems = validate_fmu(str(exported[fmi]))
    assert problems == [], "\n".join(problems)


@pytest.mark.parametrize("fmi", [2, 3])
def test_same_binaries_and_sources_start_values_and_description(
    exported, machine_file, fmu2_path, fmu3_path, fmi
) -> None:
    src = fmu2_path if fmi == 2 else fmu3_path
    with zipfile.ZipFile(src) as a, zipfile.ZipFile(exported[fmi]) as b:
        names = set(b.namelist())
        for name in a.namelist():
            if name != "modelDescription.xml" and not name.endswith("/"):
                assert name in names and a.read(name) == b.read(name), name
        assert f"resources/{START_VALUES}" in names
    md = read_model_description(str(exported[fmi]))
    model = load_model(machine_file)
    assert "test machine" in md.description and "machine.json" in md.description
    assert md.guid == read_model_description(str(src)).guid  # the binary checks it
    starts = {v.name: v.start for v in md.modelVariables}
    if fmi == 2:
        for name, value in model.fmu_parameters().items():
            assert starts[name] == literal(name, value), name
    else:
        assert starts["friction.N"] == "3" and starts["m"] == repr(23.75)
        assert starts["friction.nu"].split() == ["0.25", "0.35", "0.4"]
        assert starts["effects.ripple_aperiodic"] == "false"


@pytest.mark.parametrize("fmi", [2, 3])
def test_exported_fmu_without_parameters_is_the_model_bit_for_bit_in_fmpy(
    exported, machine_file, fmu2_path, fmu3_path, fmi
):
    model = load_model(machine_file)
    src = fmu2_path if fmi == 2 else fmu3_path
    want = _scenario(src, model.fmu_parameters())
    got = _scenario(exported[fmi])
    for c in COLUMNS:
        assert np.array_equal(got[c], want[c]), c
    paper = _scenario(src)  # the start values matter: the paper's drive differs
    assert np.max(np.abs(paper["x"] - got["x"])) > 1e-3


def _fmipp(fmu: Path, out: Path, parameters: dict | None = None) -> dict[str, np.ndarray]:
    cmd = [sys.executable, str(HERE / "fmipp_export_run.py"), str(fmu), str(out / "run.npz")]
    out.mkdir(parents=True, exist_ok=True)
    if parameters is not None:
        (out / "parameters.json").write_text(json.dumps(parameters))
        cmd.append(str(out / "parameters.json"))
    for _attempt in range(4):  # fmipp's loader aborts in ~8 % of fresh loads (test_fmipp.py)
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=600, cwd=HERE)
        if p.returncode == 0 or "No such node" not in p.stderr:
            break
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    z = np.load(out / "run.npz")
    return {c: z[c] for c in COLUMNS}


def test_exported_fmu_without_parameters_is_the_model_bit_for_bit_in_fmipp(
    exported, machine_file, fmu2_path, tmp_path
):
    pytest.importorskip("fmipp", reason="fmipp is not installed: run `make importers`")
    want = _fmipp(fmu2_path, tmp_path / "source", load_model(machine_file).fmu_parameters())
    got = _fmipp(exported[2], tmp_path / "exported")
    for c in COLUMNS:
        assert np.array_equal(got[c], want[c]), c
    assert np.ptp(got["x"]) > 0.03
    # and as fmpy's run of it, within test_fmipp.py's CS tolerance (the same calls; fmipp's
    # times k Ts and its setup differ in the last bits)
    assert np.max(np.abs(got["x"] - _scenario(exported[2])["x"])) < 1e-12


@pytest.mark.parametrize("fmi", [2, 3])
def test_ssv_reads_back_the_model_values(exported, machine_file, fmi) -> None:
    ps = read_ssv(str(exported[fmi].with_suffix(".ssv")))  # validates against SSP 1.0's schema
    model = load_model(machine_file)
    got = {p.name: p for p in ps.parameters}
    assert ps.name == "test machine" and set(got) == set(model.fmu_parameters())
    for name, value in model.fmu_parameters().items():
        p = got[name]
        if isinstance(value, bool):
            assert p.type == "Boolean" and p.value == ("true" if value else "false")
        elif isinstance(value, int):
            assert p.type == "Integer" and int(p.value) == value
        else:
            assert p.type == "Real" and float(p.value) == value, name
    assert got["m"].unit == "kg" and got["friction.k[1]"].unit == "N/m"


def test_reset_returns_to_the_exported_start_values(exported, machine_file) -> None:
    with Plant(interface="cs", path=exported[2]) as p:
        p.start()
        p.set({"m": 1.0})
        p.reset()
        p.fmu.setupExperiment(startTime=0.0)
        p.fmu.enterInitializationMode()
        assert p.get(["m", "offset.F"]) == {"m": 23.75, "offset.F": -2.125}


@pytest.mark.parametrize(
    "old,line,message",
    [
        (b"m 23.75", b"m -1.5", "start_values.txt line 2: m = -1.5: allowed"),
        (b"m 23.75", b"m 1,5", "start_values.txt line 2: m = 1,5: allowed a finite number"),
        (b"m 23.75", b"mass 20", "start_values.txt line 2: mass is not a variable of this FMU"),
        (b"m 23.75", b"x 0.1", "start_values.txt line 2: x is not a parameter"),
        (b"m 23.75", b"m 23.75 7", 'start_values.txt line 2: expected "name value"'),
        (
            b"friction.F_c 24.0",
            b"friction.F_c 40.0",
            "friction.F_c = 40 exceeds friction.F_s = 31.5",
        ),
    ],
)
def test_bad_start_value_file_fails_instantiation_naming_the_line(
    exported, tmp_path, old, line, message
):
    bad = tmp_path / "bad.fmu"
    with zipfile.ZipFile(exported[2]) as a, zipfile.ZipFile(bad, "w") as b:
        for item in a.infolist():
            data = a.read(item)
            if item.filename == f"resources/{START_VALUES}":
                assert b"\n" + old + b"\n" in data
                data = data.replace(b"\n" + old + b"\n", b"\n" + line + b"\n")
            b.writestr(item, data)
    p = Plant(interface="cs", path=bad, log=True)
    with pytest.raises(Exception):  # noqa: B017 -- fmpy raises a bare Exception when fmi2Instantiate fails
        p.start()
    assert message in "\n".join(p.messages)


def test_start_value_file_comments_and_crlf_are_read(exported, tmp_path):
    edited = tmp_path / "edited.fmu"
    with zipfile.ZipFile(exported[2]) as a, zipfile.ZipFile(edited, "w") as b:
        for item in a.infolist():
            data = a.read(item)
            if item.filename == f"resources/{START_VALUES}":
                data = data.replace(
                    b"\nm 23.75\n", b"\n# the slide with its fixture\nm 31.5  # kg\n"
                )
                data = data.replace(b"\n", b"\r\n")
            b.writestr(item, data)
    with Plant(interface="cs", path=edited) as p:
        p.start()
        assert p.get(["m", "offset.F"]) == {"m": 31.5, "offset.F": -2.125}


def test_cli_writes_refuses_existing_and_bad_model(machine_file, tmp_path, capsys) -> None:
    out = tmp_path / "MyDrive.fmu"
    assert cli.main(["fmu", str(machine_file), "--out", str(out), "--fmi", "3"]) == 0
    assert out.is_file() and out.with_suffix(".ssv").is_file()
    before = out.read_bytes()
    assert cli.main(["fmu", str(machine_file), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "exists" in err[0] and "--force" in err[0]
    assert out.read_bytes() == before
    assert cli.main(["fmu", str(machine_file), "--out", str(out), "--force"]) == 0
    assert read_model_description(str(out)).fmiVersion == "2.0"
    bad = tmp_path / "bad.json"
    bad.write_text(machine_file.read_text().replace('"m": 23.75', '"m": -1.0'))
    assert cli.main(["fmu", str(bad), "--out", str(tmp_path / "B.fmu")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(bad) in err[0] and "Traceback" not in err[0]
    assert not (tmp_path / "B.fmu").exists() and not (tmp_path / "B.ssv").exists()
    assert cli.main(["fmu", str(machine_file), "--out", str(machine_file)]) == 2
    assert "input" in capsys.readouterr().err
