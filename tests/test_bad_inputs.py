"""Every command that reads a run CSV, a sidecar or a model file (validate, diagnose, identify,
experiments, report) refuses a bad one with exit
status 2 and ONE line on stderr naming the file, never a traceback, modifying no input and
writing no output (corpus: tests/bad_corpus.py, made from one good closed-loop run)."""

from __future__ import annotations

import hashlib
import json
import re
from pathlib import Path

import pytest

from bad_corpus import csv_cases, foreign_sidecar_cases, model_cases, sidecar_cases
from diagnosis_runs import simulate_run, sinusoid_reference
from feeddrive.cli import main
from feeddrive.data import load_run, write_run
from feeddrive.harness.checked_runs import check_run
from feeddrive.identify.pipeline import classify_why
from feeddrive.model_file import paper_model, save_model

#: (case, commands that may accept it): not a broken file for that command's purpose
ACCEPTED = {("csv", "constant_x"): {"validate", "diagnose"}}  # x stuck: a gap to show


@pytest.fixture(scope="module")
def good(tmp_path_factory, fmu_path):
    d = tmp_path_factory.mktemp("good")
    run = simulate_run(
        paper_model(), sinusoid_reference(1.5, period=1.5), current_noise=0.005, seed=3, name="good"
    )
    write_run(run, d / "good.csv")
    save_model(paper_model(), d / "model.json")
    return (
        (d / "good.csv").read_text(),
        json.loads((d / "good.json").read_text()),
        json.loads((d / "model.json").read_text()),
    )


def _cases() -> list[tuple[str, str]]:
    # the names only: the texts need the good run (fixture)
    dummy_csv = "time,u,i,x,x_ref,F_load\n" + "".join(
        f"{k * 5e-4},0.{k},0.{k},0.1{k},0.1{k},0.0\n" for k in range(1, 30)
    )
    dummy_side = {"controller": {"type": "pid", "Kp": 1.0}, "sensors": {}}
    pm = paper_model()
    dummy_model = {"name": "m", "effects": dict(pm.effects), "parameters": dict(pm.parameters)}
    return (
        [("csv", n) for n, _ in csv_cases(dummy_csv)]
        + [("sidecar", n) for n, _ in sidecar_cases(dummy_side)]
        + [("model", n) for n, _ in model_cases(dummy_model)]
    )


CASES = _cases()


def test_corpus_is_large_enough():
    assert len(CASES) >= 40
    assert len(set(CASES)) == len(CASES)


def _digest(folder: Path) -> dict[str, str]:
    return {
        str(p): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def _put(path: Path, data: str | bytes) -> Path:
    path.write_bytes(data if isinstance(data, bytes) else data.encode())
    return path


@pytest.mark.parametrize("group,name", CASES, ids=[f"{g}-{n}" for g, n in CASES])
def test_bad_file_refused_by_every_command(tmp_path, capsys, good, group, name):
    good_csv, good_side, good_model = good
    text = dict(
        {"csv": csv_cases, "sidecar": sidecar_cases, "model": model_cases}[group](
            {"csv": good_csv, "sidecar": good_side, "model": good_model}[group]
        )
    )[name]
    d = tmp_path / "in"
    d.mkdir()
    run = _put(d / "run.csv", text if group == "csv" else good_csv)
    side = _put(d / "run.json", text if group == "sidecar" else json.dumps(good_side))
    model = _put(
        d / ("bad.json" if group == "model" else "model.json"),
        text if group == "model" else json.dumps(good_model),
    )
    bad = {"csv": run, "sidecar": side, "model": model}[group]
    out = tmp_path / "out"
    commands = {
        "validate": ["validate", str(run), "--model", str(model)],
        "diagnose": ["diagnose", str(run), "--model", str(model), "--out", str(out / "d")],
        "identify": ["identify", str(d), "--out", str(out / "id.json")],
        "report": ["report", str(d), "--out", str(out / "r")],
    }
    if group == "model":
        commands["identify"] += ["--truth", str(model)]
        commands["report"] += ["--truth", str(model)]
        commands["experiments"] = ["experiments", "--out", str(out / "e"), "--model", str(model)]
        commands["fmu"] = ["fmu", str(model), "--out", str(out / "m.fmu")]
    before = _digest(d)
    capsys.readouterr()
    for cmd, argv in commands.items():
        if cmd in ACCEPTED.get((group, name), ()):
            continue
        rc = main(argv)
        captured = capsys.readouterr()
        err = captured.err.strip().splitlines()
        assert rc == 2, (cmd, rc, captured.out[-500:], captured.err[-500:])
        assert len(err) == 1, (cmd, err)
        assert "Traceback" not in captured.err
        assert err[0].startswith(f"feeddrive {cmd}: ")
        assert str(bad) in err[0], (cmd, err[0])
        assert _digest(d) == before, cmd
        assert not out.exists() or not any(out.iterdir()), (cmd, list(out.iterdir()))


FOREIGN = [c[0] for c in foreign_sidecar_cases({"controller": {}, "sensors": {}})]


@pytest.mark.parametrize("name", FOREIGN)
def test_foreign_sidecar_is_read_for_what_it_says(tmp_path, good, name):
    """A sidecar is information: every key it has that the tools do not use is named in
    one line, left out of ``run.meta``, and the run stays usable."""
    good_csv, good_side, _ = good
    meta, key = next((m, k) for n, m, k in foreign_sidecar_cases(good_side) if n == name)
    _put(tmp_path / "run.csv", good_csv)
    _put(tmp_path / "run.json", json.dumps(meta))
    run = load_run(tmp_path / "run.csv")
    side = check_run(run)
    line = side.note_line("run.json")
    if key is None:  # identify's key: its classification says so
        assert line is None and "the sidecar's kind 'banana' is not one of" in classify_why(run)[1]
        return
    assert line is not None and "\n" not in line and key in line, line
    ignored = {k for k in side.ignored if "." not in k} - {"controller"}
    assert not ignored & set(run.meta), (ignored, run.meta)
    for k in side.ignored:
        if k.startswith("sensors."):
            assert k[8:] not in run.meta["sensors"]
    if name.startswith("controller") and name != "controller_law":
        assert side.controller is None and run.meta["controller"] is None
        assert "no closed-loop replay" in line
    else:
        assert side.controller == dict(good_side["controller"])


def test_validate_shows_what_it_can_with_a_foreign_controller(tmp_path, good, capsys):
    good_csv, good_side, _ = good
    _put(tmp_path / "run.csv", good_csv)
    foreign = {
        "type": "pid",
        "law": "PID, lead on D, D low-pass",
        "Kp": 2e5,
        "Ki": 3e6,
        "Kd": 3e3,
        "d_lowpass_Hz": 400.0,
        "lead_zero_Hz": 40.0,
        "force_per_volt": 78.7,
    }
    _put(tmp_path / "run.json", json.dumps(dict(good_side, controller=foreign)))
    assert main(["validate", str(tmp_path / "run.csv")]) == 0
    out = capsys.readouterr().out
    assert "ignored controller" in out and "'Kv' missing" in out and "law, Kd" in out, out
    assert "position gap not computed" in out and "position gap x_sim" not in out, out
    assert re.search(r"force residual .*: rms \d", out), out
    # diagnose uses the run and keeps the line in what it writes
    _put(tmp_path / "model.json", json.dumps(good[2]))
    assert (
        main(
            [
                "diagnose",
                str(tmp_path / "run.csv"),
                "--model",
                str(tmp_path / "model.json"),
                "--out",
                str(tmp_path / "d"),
                "--max-steps",
                "1",
            ]
        )
        == 0
    )
    notes = json.loads((tmp_path / "d" / "diagnosis.json").read_text())["notes"]
    assert any("run.json: ignored controller" in n and "'Kv' missing" in n for n in notes), notes
    assert any("closed-loop gap not computed" in n for n in notes), notes
    capsys.readouterr()
    # the same controller described with one descriptive key: replayed, the key named
    _put(
        tmp_path / "run.json",
        json.dumps(dict(good_side, controller=dict(good_side["controller"], law="PID"))),
    )
    assert main(["validate", str(tmp_path / "run.csv")]) == 0
    out = capsys.readouterr().out
    assert "ignored controller.law" in out and "position gap x_sim - x_meas" in out, out
