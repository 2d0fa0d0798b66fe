"""Where the package finds its FMU: an explicit path, else $FEEDDRIVE_FMU, else the package's
own copy (package data); a one-line error naming the places looked at; no path computed from
the source tree anywhere in the package."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import feeddrive
from feeddrive import fmu, model_description
from feeddrive.cli import main as cli
from feeddrive.fmu import FMUNotFoundError, Plant, fmu_path

PACKAGE = Path(feeddrive.__file__).parent


def test_default_is_the_package_copy(fmu_path: Path, monkeypatch):
    monkeypatch.delenv("FEEDDRIVE_FMU", raising=False)
    assert fmu.DEFAULT_FMU == PACKAGE / "LinearMotorFeedDrive.fmu"
    assert fmu.fmu_path() == fmu.DEFAULT_FMU


def test_explicit_path_wins_over_the_environment(fmu_path: Path, monkeypatch, tmp_path):
    monkeypatch.setenv("FEEDDRIVE_FMU", str(tmp_path / "nowhere.fmu"))
    assert fmu.fmu_path(fmu_path) == fmu_path
    with Plant(path=fmu_path) as plant:
        assert plant.path == fmu_path


def test_environment_wins_over_the_package(fmu_path: Path, monkeypatch, tmp_path):
    copy = tmp_path / "elsewhere.fmu"
    copy.write_bytes(fmu_path.read_bytes())
    monkeypatch.setenv("FEEDDRIVE_FMU", str(copy))
    assert fmu.fmu_path() == copy


def test_environment_naming_no_file_is_an_error_not_a_fall_back(monkeypatch, tmp_path):
    monkeypatch.setenv("FEEDDRIVE_FMU", str(tmp_path / "nowhere.fmu"))
    with pytest.raises(
        FMUNotFoundError, match=re.escape(f"FEEDDRIVE_FMU={tmp_path / 'nowhere.fmu'}: no FMU")
    ):
        fmu_path()


def test_neither_names_both_places(monkeypatch, tmp_path):
    monkeypatch.delenv("FEEDDRIVE_FMU", raising=False)
    monkeypatch.setattr(model_description, "DEFAULT_FMU", tmp_path / "LinearMotorFeedDrive.fmu")
    with pytest.raises(FMUNotFoundError) as e:
        Plant()
    msg = str(e.value)
    assert str(tmp_path / "LinearMotorFeedDrive.fmu") in msg and "FEEDDRIVE_FMU is not set" in msg
    with pytest.raises(FMUNotFoundError, match=r"nowhere\.fmu: no FMU there"):
        fmu_path(tmp_path / "nowhere.fmu")


def test_cli_without_an_fmu_prints_one_line_and_exits_2(monkeypatch, tmp_path, capsys):
    monkeypatch.setenv("FEEDDRIVE_FMU", str(tmp_path / "nowhere.fmu"))
    assert cli(["run", "--out", str(tmp_path / "report")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("feeddrive run: FEEDDRIVE_FMU=") and err.count("\n") == 1
    assert not (tmp_path / "report").exists()


def test_no_module_computes_a_path_from_its_source_file():
    hits = [
        f"{p.relative_to(PACKAGE)}:{i}: {line.strip()}"
        for p in sorted(PACKAGE.rglob("*.py"))
        for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
        if re.search(r"__file__|\.parents\[|\bREPO\b", line)
    ]
    assert not hits, "\n".join(hits)
