"""No command replaces a file without ``--force``: each command that writes refuses an existing
output (a file, or a non-empty folder feeddrive did not write) before any work, with exit
status 2 and one line naming it and ``--force``, and leaves it as it was; with ``--force`` it
writes.  ``validate`` prints numbers or why one is missing, never "nan"."""

from __future__ import annotations

import json
import re
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from diagnosis_runs import simulate_run, sinusoid_reference
from feeddrive import cli
from feeddrive.data import Run, write_run
from feeddrive.experiments.tracking_error import ErrorSummary
from feeddrive.model_file import paper_model, save_model
from feeddrive.systems import sec3_system
from feeddrive.validation.replay import ValidationReport

#: a tiny sweep (two runs of 0.2 s) on a model file beside the study
STUDY = {
    "schema": "feeddrive.study/1",
    "name": "force",
    "model": "base_model.json",
    "experiment": {
        "reference": {
            "type": "sinusoid",
            "amplitude": 0.005,
            "period": 0.2,
            "centre": 0.15,
            "duration": 0.2,
        },
        "controller": {"type": "pid"},
        "skip_start": 0.0,
        "half_width": 0.05,
    },
    "parameters": {"m": {"relative": 0.1}},
    "design": {"type": "grid", "levels": 2},
    "metrics": ["rms_error"],
}


@pytest.fixture(scope="module")
def inputs(tmp_path_factory, fmu_path) -> Path:
    """A folder with a model file, one closed-loop run (and sidecar) and a study file."""
    d = tmp_path_factory.mktemp("in")
    save_model(paper_model(), d / "base_model.json")
    run = simulate_run(
        paper_model(), sinusoid_reference(1.5, period=1.5), current_noise=0.005, seed=3, name="r"
    )
    (d / "runs").mkdir()
    write_run(run, d / "runs" / "r.csv")
    (d / "study.json").write_text(json.dumps(STUDY))
    return d


def _files(root: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()
    }


def _refused(argv: list[str], name: str, target: Path, capsys) -> None:
    before = _files(target) if target.is_dir() else target.read_bytes()
    capsys.readouterr()
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"feeddrive {name}: "), err
    assert str(target) in err[0] and "--force" in err[0], err[0]
    assert (_files(target) if target.is_dir() else target.read_bytes()) == before


def _foreign_folder(path: Path) -> Path:
    """A non-empty folder feeddrive did not write (no .feeddrive-output)."""
    path.mkdir()
    (path / "notes.txt").write_text("mine\n")
    return path


def _argv(name: str, inputs: Path, out: Path) -> list[str]:
    """A cheap command line of ``name`` writing to ``out``."""
    d = inputs
    return {
        "run": ["run", "--out", str(out)],
        "report": ["report", str(d / "runs"), "--out", str(out)],
        "model": ["model", "--paper", "--out", str(out)],
        "system": ["system", "--out", str(out)],
        "circle": ["circle", "--radius-mm", "5", "--feed-m-min", "2", "--out", str(out)],
        "experiments": ["experiments", "--out", str(out)],
        "identify": ["identify", str(d / "runs"), "--out", str(out)],
        "diagnose": [
            "diagnose",
            str(d / "runs" / "r.csv"),
            "--model",
            str(d / "base_model.json"),
            "--out",
            str(out),
        ],
        "sweep": ["sweep", str(d / "study.json"), "--out", str(out), "--serial"],
        "fmu": ["fmu", str(d / "base_model.json"), "--out", str(out)],
        "plan": ["plan", "--out", str(out)],
    }[name]


WRITERS = sorted(
    n
    for n, r in cli.path_roles(cli.build_parser()).items()
    if set(r.values()) & set(cli.OUTPUT_ROLES)
)


def test_the_cases_cover_every_command_that_writes(tmp_path):
    assert set(WRITERS) == {
        "run",
        "report",
        "model",
        "system",
        "circle",
        "experiments",
        "identify",
        "diagnose",
        "sweep",
        "fmu",
        "plan",
    }


@pytest.mark.parametrize("name", WRITERS)
def test_an_existing_output_is_refused_without_force(name, inputs, tmp_path, capsys):
    if name in ("model", "identify"):  # a file
        target = tmp_path / "model.json"
        target.write_text("{}\n")
    elif name == "fmu":  # the FMU file
        target = tmp_path / "MyDrive.fmu"
        target.write_bytes(b"mine")
    elif name == "system":  # one of the case's files in the folder
        target = tmp_path / "sys"
        target.mkdir()
        (target / f"{sec3_system().name}.ssp").write_bytes(b"mine")
    else:
        target = _foreign_folder(tmp_path / "out")
    _refused(_argv(name, inputs, target), name, target, capsys)


def test_model_replaced_with_force(tmp_path, capsys):
    out = tmp_path / "model.json"
    out.write_text("{}\n")
    assert cli.main(["model", "--paper", "--out", str(out), "--force"]) == 0
    assert json.loads(out.read_text())["parameters"]["friction.F_s"] == 26.1


def _rows(path: Path) -> list[tuple[str, ...]]:
    """The rows of a results table without the wall time."""
    lines = [ln.split(",") for ln in path.read_text().splitlines()]
    wall = lines[0].index("wall_s")
    return [tuple(c for k, c in enumerate(ln) if k != wall) for ln in lines[1:]]


def test_sweep_results_kept_without_force_replaced_with_it(inputs, tmp_path, capsys):
    out = tmp_path / "s"
    assert cli.main(_argv("sweep", inputs, out)) == 0
    first = _rows(out / "results.csv")
    _refused(_argv("sweep", inputs, out), "sweep", out, capsys)
    (out / "results.csv").write_text("damaged\n")
    assert cli.main([*_argv("sweep", inputs, out), "--force"]) == 0
    assert _rows(out / "results.csv") == first and len(first) == 2
    capsys.readouterr()
    assert cli.main([*_argv("sweep", inputs, out), "--force", "--resume"]) == 2
    assert "one of --force" in capsys.readouterr().err


# ---------------------------------------------------------------- validate: no nan


def test_validate_text_says_why_a_figure_is_missing(inputs):
    nan = float("nan")
    rep = ValidationReport(
        run=Run(time=np.zeros(1), u=np.zeros(1), x=np.zeros(1)),
        model_name="paper",
        position=ErrorSummary(nan, nan, nan, []),
        force={"rms": 0.5, "peak": 1.5},
    )
    text = rep.text()
    assert "nan" not in text.lower()
    assert text.count("not computed: ") == 3
    assert "no reversal of x_ref" in text


def test_validate_of_runs_without_a_reversal_or_a_reference_prints_no_nan(inputs, tmp_path, capsys):
    # a 1 s closed-loop run of a 6 s sinusoid: no reversal after the first 0.5 s
    run = simulate_run(
        paper_model(),
        sinusoid_reference(1.0, period=6.0),
        current_noise=0.005,
        seed=4,
        name="short",
    )
    write_run(run, tmp_path / "short.csv")
    # the same run without reference nor controller: the force residual only
    write_run(replace(run, x_ref=None, meta={"name": "noref"}, path=None), tmp_path / "noref.csv")
    for name, why in (
        ("short", "not computed: no reversal of x_ref"),
        ("noref", "the closed-loop position gap is not computed"),
    ):
        capsys.readouterr()
        assert cli.main(["validate", str(tmp_path / f"{name}.csv")]) == 0
        out = capsys.readouterr().out
        assert why in out, out
        assert not re.search(r"\bnan\b", out, re.IGNORECASE), out
        assert re.search(r"rms \d+\.\d{3}", out), out  # the force residual [N]
    assert re.search(r"rms: \d+\.\d\d µm", out) is None  # noref: no position figures


def test_progress_on_a_terminal_only(tmp_path, capsys, monkeypatch, fmu_path):
    """validate's stages on stderr when it is a terminal; nothing when it is not (a pipe, a
    file, a test's capture) or with --no-progress."""
    run = simulate_run(paper_model(), sinusoid_reference(1.0, period=6.0), name="p")
    write_run(run, tmp_path / "p.csv")
    argv = ["validate", str(tmp_path / "p.csv")]
    capsys.readouterr()
    assert cli.main(argv) == 0
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    assert cli.main(argv) == 0
    err = capsys.readouterr().err
    assert "validate: 3 stages" in err and "force residual" in err, err
    assert cli.main([*argv, "--no-progress"]) == 0
    assert capsys.readouterr().err == ""
