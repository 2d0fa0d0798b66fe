"""Parameter studies (feeddrive.study): the study file, the samplers, a failing run as a row,
serial = LocalCluster = external scheduler bitwise, resume, the force-residual metric, the
report and the `feeddrive sweep` command."""

from __future__ import annotations

import copy
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from distributed import LocalCluster

from feeddrive.bench_study import study_rows
from feeddrive.data import write_run
from feeddrive.harness import closed_loop_run, pid_spec, run_closed_loop, sinusoid
from feeddrive.harness.sensors import Sensors
from feeddrive.paper import paper_parameters
from feeddrive.report.study import write_study_report
from feeddrive.study import (
    FAILED,
    OK,
    Case,
    RunTask,
    StudyError,
    cases,
    load_study,
    parse_study,
    read_table,
    run_case,
    run_study,
)
from feeddrive.study.run import make_reference

BASE = {
    "schema": "feeddrive.study/1",
    "name": "t",
    "experiment": {
        "reference": {
            "type": "sinusoid",
            "amplitude": 0.005,
            "period": 0.4,
            "centre": 0.15,
            "duration": 0.5,
        },
        "controller": {"type": "pid"},
        "skip_start": 0.05,
        "half_width": 0.05,
    },
    "parameters": {"friction.F_s": {"low": 20.0, "high": 32.0}, "m": {"relative": 0.2}},
    "design": {"type": "lhs", "runs": 12, "seed": 3},
    "metrics": ["reversal_error", "rms_error", "max_error"],
    "batch_size": 2,
}


def _write(tmp: Path, doc: dict, name: str = "study.json") -> Path:
    p = tmp / name
    p.write_text(json.dumps(doc))
    return p


def _same(a: list[dict], b: list[dict], cols: tuple[str, ...]) -> None:
    assert [r["run"] for r in a] == [r["run"] for r in b]
    for ra, rb in zip(a, b, strict=True):
        assert (ra["status"], ra["message"]) == (rb["status"], rb["message"])
        for c in cols:
            x, y = ra[c], rb[c]
            assert (math.isnan(x) and math.isnan(y)) or x == y, (ra["run"], c, x, y)


# ------------------------------------------------------------------ study file
def _edit(path: list, value) -> dict:
    doc = copy.deepcopy(BASE)
    d = doc
    for k in path[:-1]:
        d = d[k]
    if value is _DELETE:
        del d[path[-1]]
    else:
        d[path[-1]] = value
    return doc


_DELETE = object()
BAD = [
    (["schema"], "feeddrive.study/0", "field schema"),
    (["design"], _DELETE, "field design"),
    (["design", "type"], "sobol", "field design.type"),
    (["design", "type"], ["lhs"], "field design.type"),  # a type that is no name
    (["design", "runs"], 0, "field design.runs"),
    (["metrics"], ["reversal_error", "iso230"], "field metrics[1]"),
    (["parameters", "mass"], {"low": 1, "high": 2}, "field parameters['mass']"),
    (["parameters", "m"], {"low": 20, "high": 10}, "field parameters['m'].high"),
    (
        ["parameters", "m"],
        {"distribution": "nosuch", "loc": 1},
        "field parameters['m'].distribution",
    ),
    (["parameters", "m"], {"values": [15, 16]}, "field parameters['m']"),  # values: grid only
    (["experiment", "reference", "type"], "circle", "field experiment.reference.type"),
    (["experiment", "reference", "period"], -1, "field experiment.reference.period"),
    (["experiment", "controller", "type"], "lqr", "field experiment.controller.type"),
    (["experiment", "controller", "type"], {"pid": 1}, "field experiment.controller.type"),
    (["experiment", "reference", "type"], ["sinusoid"], "field experiment.reference.type"),
    (["experiment", "measured"], "nothere.csv", "field experiment.measured"),
    (["metrics"], ["force_residual"], "field experiment.measured"),
    (["batch_size"], 0, "field batch_size"),
    (["extra"], 1, "field (top level).extra"),
]


@pytest.mark.parametrize("path,value,field", BAD, ids=[b[2] for b in BAD])
def test_bad_study_file_names_file_and_field(tmp_path: Path, path, value, field) -> None:
    p = _write(tmp_path, _edit(path, value))
    with pytest.raises(StudyError) as e:
        load_study(p)
    msg = str(e.value)
    assert msg.startswith(f"{p}: {field}") and "\n" not in msg


def test_bad_study_file_on_the_command_line(tmp_path: Path) -> None:
    p = tmp_path / "study.json"
    p.write_text('{"schema": "feeddrive.study/1",\n "design": ')
    out = subprocess.run(
        [sys.executable, "-m", "feeddrive.cli", "sweep", str(p), "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 2
    assert out.stderr.strip().count("\n") == 0 and "Traceback" not in out.stderr
    assert str(p) in out.stderr and "invalid JSON at line 2" in out.stderr
    assert not (tmp_path / "o").exists()


# ------------------------------------------------------------------ samplers
def test_samplers(tmp_path: Path) -> None:
    lhs = cases(parse_study(BASE, "s", tmp_path))
    assert [c.run for c in lhs] == list(range(12))
    # Latin hypercube: each parameter has exactly one value in each of the 12 strata
    for name, (lo, hi) in (("friction.F_s", (20.0, 32.0)), ("m", (16.1 * 0.8, 16.1 * 1.2))):
        v = np.array([c.values[name] for c in lhs])
        strata = np.floor((v - lo) / (hi - lo) * 12).astype(int)
        assert sorted(strata) == list(range(12))
    assert [c.values for c in cases(parse_study(BASE, "s", tmp_path))] == [c.values for c in lhs]
    grid = _edit(["design"], {"type": "grid", "levels": 3})
    grid["parameters"]["friction.N"] = {"values": [2, 4.6]}
    g = cases(parse_study(grid, "s", tmp_path))
    assert len(g) == 3 * 3 * 2
    assert {c.values["friction.N"] for c in g} == {2, 5}
    assert all(isinstance(c.values["friction.N"], int) for c in g)
    mc = _edit(["design"], {"type": "monte_carlo", "runs": 4000, "seed": 1})
    mc["parameters"]["m"] = {"distribution": "norm", "loc": 16.1, "scale": 0.5}
    m = np.array([c.values["m"] for c in cases(parse_study(mc, "s", tmp_path))])
    assert abs(m.mean() - 16.1) < 4 * 0.5 / math.sqrt(4000) and abs(m.std() - 0.5) < 0.03
    oat = cases(parse_study(_edit(["design"], {"type": "oat"}), "s", tmp_path))
    assert [c.label for c in oat] == [
        "base",
        "friction.F_s=low",
        "friction.F_s=high",
        "m=low",
        "m=high",
    ]
    assert oat[0].values == {
        "friction.F_s": paper_parameters()["friction.F_s"],
        "m": paper_parameters()["m"],
    }
    assert oat[3].values["m"] == pytest.approx(16.1 * 0.8) and oat[3].values["friction.F_s"] == 26.1


# ------------------------------------------------------------------ execution
def test_serial_local_cluster_and_scheduler_give_the_same_table(tmp_path: Path) -> None:
    """12 runs of 0.5 s (some fail: F_s below the paper's F_c = 21.6 N is refused by the
    model's rules): serial, a LocalCluster of 2 workers, a scheduler started here on
    127.0.0.1: the same rows, bit for bit."""
    study = load_study(_write(tmp_path, BASE))
    serial = run_study(study, tmp_path / "serial", parallel=False)
    assert serial.n_runs == len(serial.rows) == 12 and serial.missing == 0
    failed = [r for r in serial.rows if r["status"] == FAILED]
    ok = [r for r in serial.rows if r["status"] == OK]
    assert failed and ok
    assert all(r["friction.F_s"] < 21.6 for r in failed)
    assert all("friction.F_c" in r["message"] and math.isnan(r["rms_error_m"]) for r in failed)
    assert all(0 < r["rms_error_m"] < r["max_error_m"] < 1e-3 for r in ok)
    cols = study.parameter_names + study.metric_columns
    local = run_study(study, tmp_path / "local", workers=2)
    _same(serial.rows, local.rows, cols)
    with LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        host="127.0.0.1",
        scheduler_port=0,
        dashboard_address=None,
    ) as cluster:
        assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
        remote = run_study(study, tmp_path / "remote", scheduler=cluster.scheduler_address)
    _same(serial.rows, remote.rows, cols)
    _same(serial.rows, read_table(tmp_path / "local" / "results.parquet"), cols)
    # the CSV gives back the same float64 bits
    again = run_study(study, tmp_path / "serial", resume=True, parallel=False)
    assert again.computed == 0
    _same(serial.rows, again.rows, cols + ("wall_s",))


def test_resume_computes_only_the_missing_runs(tmp_path: Path) -> None:
    doc = _edit(["design"], {"type": "lhs", "runs": 6, "seed": 1})
    doc["experiment"]["reference"]["duration"] = 0.2
    study = load_study(_write(tmp_path, doc))
    full = run_study(study, tmp_path / "a", parallel=False)
    csv = tmp_path / "a" / "results.csv"
    lines = csv.read_text().splitlines()
    csv.write_text("\n".join(lines[:3] + [lines[5][:20]]) + "\n")  # 2 rows and a torn line
    with pytest.raises(ValueError, match="--resume"):
        run_study(study, tmp_path / "a", parallel=False)
    res = run_study(study, tmp_path / "a", resume=True, parallel=False)
    assert res.computed == 4 and len(res.rows) == 6
    _same(full.rows, res.rows, study.parameter_names + study.metric_columns)
    other = load_study(_write(tmp_path, _edit(["design", "seed"], 2), "other.json"))
    with pytest.raises(ValueError, match="another study"):
        run_study(other, tmp_path / "a", resume=True, parallel=False)


def test_force_residual_metric_and_report(tmp_path: Path) -> None:
    """Against a run measured on the paper's model, the residual is smallest at the true mass
    and grows by about |dm| * rms(a) at the ends of a one-at-a-time study."""
    ref = sinusoid(0.010, 0.5, 0.15, 1.0)
    run, res = closed_loop_run(
        paper_parameters(), pid_spec(), ref, Sensors(quantum=1e-7, current_noise=0.0)
    )
    write_run(run, tmp_path / "measured.csv")
    doc = copy.deepcopy(BASE)
    doc["experiment"]["measured"] = "measured.csv"
    doc["parameters"] = {"m": {"relative": 0.1}}
    doc["design"] = {"type": "oat"}
    doc["metrics"] = ["force_residual", "rms_error"]
    study = load_study(_write(tmp_path, doc))
    out = run_study(study, tmp_path / "o", parallel=False)
    r = {row["label"]: row["force_residual_N"] for row in out.rows}
    a_rms = float(np.sqrt(np.mean(np.asarray(res["a"])[100:-100] ** 2)))
    assert r["base"] < 0.2 * 0.1 * 16.1 * a_rms
    for end in ("m=low", "m=high"):
        assert r[end] == pytest.approx(0.1 * 16.1 * a_rms, rel=0.25)
    s = {(x.parameter, x.metric): x for x in out.sensitivities}
    assert s[("m", "force_residual_N")].low > 0 and s[("m", "force_residual_N")].high > 0
    page = write_study_report(out, tmp_path / "o")
    text = page.read_text()
    for png in ("study_histograms", "study_scatter", "study_tornado"):
        assert (tmp_path / "o" / f"{png}.png").stat().st_size > 1000 and png in text


def test_sweep_command_prints_the_sensitivity_table(tmp_path: Path) -> None:
    doc = _edit(["design"], {"type": "oat"})
    doc["parameters"] = {"m": {"relative": 0.2}, "friction.sigma2": {"relative": 0.5}}
    doc["experiment"]["reference"]["duration"] = 0.3
    p = _write(tmp_path, doc)
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "feeddrive.cli",
            "sweep",
            str(p),
            "--out",
            str(tmp_path / "o"),
            "--serial",
            "--no-progress",
        ],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stderr
    assert "change at low" in out.stdout and "rms_error_m" in out.stdout
    assert (tmp_path / "o" / "report.html").is_file()
    assert (tmp_path / "o" / "results.parquet").is_file()


def test_bench_study_rows_give_figures() -> None:
    """`make bench`'s study rows run (tiny study here; the figures are not judged)."""
    rows = study_rows(n_runs=8)
    names = [r[0] for r in rows]
    assert any("memory per live instance" in n for n in names)
    assert any("speed-up" in n for n in names)
    assert all("0 failed" in r[1] for r in rows if r[0].startswith("study of 8 runs"))


def test_readme_example_study_runs(tmp_path: Path) -> None:
    text = (Path(__file__).resolve().parents[1] / "docs" / "studies.md").read_text()
    section = text.split("# Parameter studies", 1)[1]
    docs = [json.loads(b.split("```", 1)[0]) for b in section.split("```json")[1:]]
    doc = next(d for d in docs if d["name"] == "friction and mass, one at a time")
    doc["experiment"]["reference"]["duration"] = 0.6  # shorter here: one top reversal
    res = run_study(parse_study(doc, "docs/studies.md", tmp_path), tmp_path / "o", parallel=False)
    assert res.failed == 0 and len(res.rows) == 1 + 2 * len(doc["parameters"])
    top = [s for s in res.sensitivities if s.metric == "reversal_error_m"]
    # more Coulomb friction, more error at the reversal; a heavier stage lags more
    assert all(s.low < 0 < s.high for s in top if s.parameter in ("friction.F_c", "m"))


def test_a_run_equals_a_fresh_closed_loop(tmp_path: Path) -> None:
    """The process's reused Plant and controller give what a fresh harness run gives, also
    after a failed run and runs with other parameters."""
    doc = copy.deepcopy(BASE)
    doc["experiment"]["sensors"] = {"quantum": 1e-7, "current_noise": 0.01, "seed": 4}
    study = parse_study(doc, "s", tmp_path)
    task = RunTask.of(study)
    values = {"friction.F_s": 30.0, "m": 18.0}
    first = run_case(task, Case(0, "", values))
    run_case(task, Case(1, "", {"friction.F_s": 10.0, "m": 18.0}))  # refused: F_s < F_c
    run_case(task, Case(2, "", {"friction.F_s": 25.0, "m": 14.0}))
    again = run_case(task, Case(3, "", values))
    ref = make_reference(study.experiment.reference)
    p = dict(paper_parameters(), **values)
    sens = study.experiment.sensors
    res = run_closed_loop(p, study.experiment.controller, ref, sensors=sens)
    e = ref.x - res["x"]
    k0 = int(round(0.05 / ref.Ts))
    assert first["status"] == again["status"] == OK
    assert first["max_error_m"] == again["max_error_m"] == float(np.max(np.abs(e[k0:])))
    assert first["rms_error_m"] == again["rms_error_m"]
