"""Outputs (feeddrive.outputs and the commands that use it): checked before any work, never
over an input, one run's results per folder, atomic files, numbers range-checked."""

from __future__ import annotations

import json

import pytest

from diagnosis_runs import simulate_run, sinusoid_reference
from feeddrive import cli
from feeddrive.data import write_run
from feeddrive.experiments import campaign as campaign_mod
from feeddrive.model_file import load_model, paper_model, save_model
from feeddrive.outputs import MARKER, OutputError, check_dir, check_file, output_dir, write_text

PAPER = paper_model()


def test_output_dir_replaces_whole_folder_and_leaves_no_stale_file(tmp_path):
    out = tmp_path / "o"
    with output_dir(out) as d:
        for k in range(3):
            (d / f"step{k}.txt").write_text("x")
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [MARKER, "step0.txt", "step1.txt", "step2.txt"]
    )
    with output_dir(out) as d:  # a rerun that writes fewer files
        (d / "step0.txt").write_text("y")
    assert sorted(p.name for p in out.iterdir()) == sorted([MARKER, "step0.txt"])
    assert [p.name for p in tmp_path.iterdir()] == ["o"]  # no staging folder left


def test_output_dir_keeps_the_old_results_when_the_work_fails(tmp_path):
    out = tmp_path / "o"
    with output_dir(out) as d:
        (d / "a.txt").write_text("old")
    with pytest.raises(RuntimeError), output_dir(out) as d:
        (d / "a.txt").write_text("new")
        raise RuntimeError("work failed")
    assert (out / "a.txt").read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["o"]


def test_foreign_folder_refused_unless_force(tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.tex").write_text("precious")
    with pytest.raises(OutputError, match=r"mine: is a non-empty folder not written by feeddrive"):
        check_dir(out)
    with output_dir(out, force=True) as d:
        (d / "r.txt").write_text("r")
    assert not (out / "thesis.tex").exists() and (out / MARKER).is_file()
    (tmp_path / "empty").mkdir()
    assert check_dir(tmp_path / "empty") == tmp_path / "empty"  # empty: fine


def test_inputs_and_unwritable_targets_refused(tmp_path, monkeypatch):
    model = tmp_path / "D" / "model.json"
    model.parent.mkdir()
    save_model(PAPER, model)
    with pytest.raises(OutputError, match="holds an input"):
        check_dir(tmp_path / "D", inputs=[model], force=True)
    with pytest.raises(OutputError, match="is an input"):
        check_file(model, inputs=[model])
    with pytest.raises(OutputError, match="is a folder"):
        check_file(tmp_path / "D")
    (tmp_path / "f").write_text("a file")
    with pytest.raises(OutputError, match="cannot write in"):
        check_file(tmp_path / "f" / "m.json")  # parent is a file
    with pytest.raises(OutputError, match="not a folder"):
        check_dir(tmp_path / "f")
    monkeypatch.chdir(tmp_path / "D")
    with pytest.raises(OutputError, match="working directory"):
        check_dir(tmp_path, force=True)


def test_write_text_is_atomic_and_leaves_no_temporary(tmp_path):
    p = tmp_path / "m.json"
    write_text(p, "one\n")
    write_text(p, "two\n")
    assert p.read_text() == "two\n" and [q.name for q in tmp_path.iterdir()] == ["m.json"]


@pytest.fixture(scope="module")
def measured(tmp_path_factory, fmu_path):
    d = tmp_path_factory.mktemp("measured")
    write_run(
        simulate_run(
            PAPER, sinusoid_reference(3.0, period=3.0), current_noise=0.005, seed=61, name="short"
        ),
        d / "short.csv",
    )
    return d / "short.csv"


def test_diagnose_refuses_out_holding_its_model_before_any_work(tmp_path, capsys, measured):
    D = tmp_path / "D"
    D.mkdir()
    save_model(PAPER.with_effect("prerolling", False), D / "model.json")
    before = (D / "model.json").read_bytes()
    assert (
        cli.main(
            [
                "diagnose",
                str(measured),
                "--model",
                str(D / "model.json"),
                "--out",
                str(D),
                "--force",
            ]
        )
        == 2
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "holds an input" in err[0] and str(D) in err[0]
    assert (D / "model.json").read_bytes() == before


def test_diagnose_rerun_holds_one_runs_results(tmp_path, capsys, measured):
    save_model(PAPER, tmp_path / "paper.json")
    out = tmp_path / "o"
    out.mkdir()
    (out / "model_step7.json").write_text("{}")  # ours from an older run
    (out / MARKER).write_text("{}")
    assert (
        cli.main(
            [
                "diagnose",
                str(measured),
                "--model",
                str(tmp_path / "paper.json"),
                "--out",
                str(out),
                "--max-steps",
                "1",
                "--no-closed-loop",
            ]
        )
        == 0
    )
    names = {p.name for p in out.iterdir()}
    assert "model_step7.json" not in names and {"diagnosis.json", "model.json", MARKER} <= names
    assert json.loads((out / "diagnosis.json").read_text())["steps"] == []
    assert "report.html" in capsys.readouterr().out


def test_experiments_unwritable_out_fails_before_the_campaign(tmp_path, capsys, monkeypatch):
    ran = []
    monkeypatch.setattr(campaign_mod, "campaign", lambda *a, **k: ran.append(1) or {})
    (tmp_path / "runs").mkdir()
    (tmp_path / "runs" / "notes.txt").write_text("not ours")
    assert cli.main(["experiments", "--out", str(tmp_path / "runs")]) == 2
    assert "not written by feeddrive" in capsys.readouterr().err and not ran
    (tmp_path / "file").write_text("x")
    assert cli.main(["experiments", "--out", str(tmp_path / "file" / "runs")]) == 2
    assert "cannot write in" in capsys.readouterr().err and not ran


def test_model_and_identify_out_checked_first(tmp_path, capsys):
    (tmp_path / "dir.json").mkdir()
    assert cli.main(["model", "--paper", "--out", str(tmp_path / "dir.json")]) == 2
    assert "is a folder" in capsys.readouterr().err
    assert (
        cli.main(["identify", str(tmp_path / "nowhere"), "--out", str(tmp_path / "dir.json")]) == 2
    )
    assert "is a folder" in capsys.readouterr().err
    truth = tmp_path / "t.json"
    save_model(PAPER, truth)
    assert cli.main(["identify", str(tmp_path), "--out", str(truth), "--truth", str(truth)]) == 2
    assert "is an input" in capsys.readouterr().err
    assert load_model(truth).parameters == PAPER.parameters


@pytest.mark.parametrize(
    "option,value,word",
    [
        ("--force-gain", "0", "> 0"),
        ("--force-gain", "-5", "> 0"),
        ("--force-gain", "inf", "> 0"),
        ("--force-gain", "x", "not a number"),
        ("--max-steps", "0", ">= 1"),
        ("--blocks", "1", ">= 2"),
        ("--window", "4", "odd integer >= 5"),
        ("--window", "6", "odd integer >= 5"),
        ("--window", "3", "odd integer >= 5"),
        ("--max-steps", "1.5", "not an integer"),
    ],
)
def test_cli_numbers_range_checked(tmp_path, capsys, option, value, word):
    with pytest.raises(SystemExit) as e:
        cli.main(
            ["diagnose", "r.csv", "--model", "m.json", "--out", str(tmp_path / "o"), option, value]
        )
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert option in err and word in err and "Traceback" not in err


def test_seed_range_checked(capsys, tmp_path):
    with pytest.raises(SystemExit):
        cli.main(["experiments", "--out", str(tmp_path / "e"), "--seed", "-1"])
    assert ">= 0" in capsys.readouterr().err
