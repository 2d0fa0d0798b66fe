"""Runs in the wrong units and folders that identify nothing are refused with one line and
exit status 2 by every command that reads runs; good recordings (the EMPS drive, the
project's own runs) pass."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from feeddrive.cli import main as feeddrive_cli
from feeddrive.data import DataError, Run, load_run, write_run
from feeddrive.diagnose.emps import emps_baseline_model
from feeddrive.harness.checked_runs import check_run
from feeddrive.model_file import save_model
from feeddrive.plausibility import A_MAX, I_MAX, V_MAX, check_units
from feeddrive.realdata.odrive import COUNTS_PER_REV, load_slow_run

SHARED = Path(__file__).resolve().parents[2] / "shared"
EMPS = SHARED / "realdata" / "emps" / "emps_train.csv"


def _one_line_rc2(capsys, argv: list[str]) -> str:
    rc = feeddrive_cli(argv)
    err = capsys.readouterr().err
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


def _sine_run(
    n: int = 4000, Ts: float = 5e-4, amp: float = 0.005, period: float = 1.0, current: float = 1.0
) -> Run:
    """A closed-loop-looking sinusoid at mid-stroke with a current and an amplifier reference."""
    t = np.arange(n) * Ts
    x = 0.15 + amp * np.sin(2 * np.pi * t / period)
    a = -amp * (2 * np.pi / period) ** 2 * np.sin(2 * np.pi * t / period)
    i = current * a / max(float(np.abs(a).max()), 1e-12)
    return Run(time=t, u=i / 1.126, i=i, x=np.round(x, 7), x_ref=x, meta={"name": "sine"})


@pytest.fixture(scope="module")
def emps() -> Run:
    return load_run(EMPS)


def test_real_and_own_recordings_pass(emps):
    # EMPS: 0 .. 0.246 m, 0.13 m/s, 1.3 m/s^2, |u| 4.3 V: far inside every bound
    check_units(emps, (-0.01, 0.3))
    check_run(emps, emps_baseline_model())
    check_run(_sine_run(current=40.0))
    # the margins the bounds keep over the EMPS drive (the argument of the thresholds)
    v = np.abs(emps.x[10:] - emps.x[:-10]).max() / (10 * emps.Ts)
    assert 0.1 < v < 0.15 and V_MAX / v > 100 and A_MAX / 1.3 > 1000


ODRIVE = SHARED / "realdata" / "odrive-cogging"
#: arc length per revolution of the ODrive's rotor taken as a linear axis [m] (a 16 mm radius)
ODRIVE_M_PER_REV = 0.1


def test_odrive_slow_runs_as_a_linear_axis_pass():
    # the measured ODrive runs (rotary, 0.03 and 0.1 rev/s, 1 revolution, Iq up to 2.1 A; one
    # run starts with a 0.19 rev jump of the counter) as arc length on the rotor: accepted;
    # the same in mm: refused
    paths = sorted(ODRIVE.glob("slow2*/*.npy"))
    assert len(paths) == 10
    for p in paths:
        sr = load_slow_run(p)
        x = sr.position / COUNTS_PER_REV * ODRIVE_M_PER_REV
        run = Run(time=sr.time, u=sr.current, i=sr.current, x=x, meta={"name": p.stem})
        check_units(run, (0.0, 0.3))
        with pytest.raises(DataError, match="positions in mm"):
            check_units(dataclasses.replace(run, x=(x + 0.05) * 1e3), (0.0, 0.3))


@pytest.mark.parametrize("scale, unit", [(1e3, "mm"), (1e6, "um")])
def test_positions_not_in_metres_are_refused_naming_the_unit(emps, scale, unit):
    bad = dataclasses.replace(emps, x=emps.x * scale, x_ref=emps.x_ref * scale)
    with pytest.raises(
        DataError, match=rf"column 'x'.*outside the model's stroke.*positions in {unit}\?"
    ):
        check_units(bad, (-0.01, 0.3))


def test_speed_and_acceleration_beyond_any_drive_are_refused():
    # a 2 mm sinusoid written in mm near the stroke's origin stays inside the widened stroke:
    # its speed (42 mm/s -> 42 "m/s") gives it away
    r = _sine_run(amp=0.002, period=0.3)
    mm = dataclasses.replace(r, x=(r.x - 0.15) * 1e3, x_ref=None)
    with pytest.raises(DataError, match=r"speed .* beyond 20 m/s.*positions in mm\?"):
        check_units(mm)
    # a 0.12 mm, 25 Hz shake in mm: slow enough (17 "m/s" over 10 ms), but 2400 "m/s^2"
    shake = _sine_run(amp=0.12e-3, period=0.04)
    shake = dataclasses.replace(shake, x=(shake.x - 0.15) * 1e3, x_ref=None)
    with pytest.raises(DataError, match=r"acceleration .* beyond 2000 m/s\^2.*positions in mm\?"):
        check_units(shake)


def test_current_in_milliamperes_is_refused():
    r = _sine_run(current=2.0)
    bad = dataclasses.replace(r, i=r.i * 1e3)
    with pytest.raises(
        DataError, match=r"column 'i'.*current -?2000 is beyond \+-1000 A.*i in mA\?"
    ):
        check_units(bad)
    check_units(dataclasses.replace(r, i=r.i * 0.99 * I_MAX / 2.0))  # 990 A: allowed


@pytest.fixture(scope="module")
def mm_files(tmp_path_factory, emps):
    d = tmp_path_factory.mktemp("mm")
    runs = d / "runs"
    runs.mkdir()
    csv = runs / "emps_mm.csv"
    write_run(dataclasses.replace(emps, x=emps.x * 1e3, x_ref=emps.x_ref * 1e3), csv)
    model = d / "emps.json"
    save_model(emps_baseline_model(), model)
    return csv, model


def test_validate_diagnose_identify_refuse_mm_positions(capsys, tmp_path, mm_files):
    csv, model = mm_files
    before = csv.read_bytes()
    for argv in (
        ["validate", str(csv), "--model", str(model)],
        [
            "diagnose",
            str(csv),
            "--model",
            str(model),
            "--out",
            str(tmp_path / "d"),
            "--force-gain",
            "35.15",
        ],
        ["identify", str(csv.parent), "--out", str(tmp_path / "m.json")],
    ):
        line = _one_line_rc2(capsys, argv)
        assert line.startswith(f"feeddrive {argv[0]}: {csv}, line ") and "column 'x'" in line, line
        assert "positions in mm?" in line, line
    assert csv.read_bytes() == before
    assert not (tmp_path / "m.json").exists() and not (tmp_path / "d" / "model.json").exists()


def test_identify_that_identifies_nothing_exits_2_with_the_reasons(capsys, tmp_path):
    runs = tmp_path / "runs"
    runs.mkdir()
    # one closed-loop sinusoid: a periodic run, but pre-rolling needs a small and a large
    # one; no PRBS, constant-speed, open-loop or variable-speed run
    write_run(_sine_run(), runs / "sine0.csv")
    out = tmp_path / "model.json"
    line = _one_line_rc2(capsys, ["identify", str(runs), "--out", str(out)])
    assert line.startswith("feeddrive identify: identify: nothing identified"), line
    for reason in (
        "current loop: no PRBS run",
        "position maps: no loaded constant-speed runs",
        "mass: no open-loop force run",
        "attraction: no variable-speed run",
        "pre-rolling: 1 periodic runs",
        "sine0 prerolling",
    ):
        assert reason in line, line
    assert not out.exists()
