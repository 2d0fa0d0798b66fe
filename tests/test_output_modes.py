"""Outputs follow the process umask: a file written is 0666 & ~umask, a folder 0777 & ~umask
(what ``open`` and ``mkdir`` give), never the 0600/0700 of a temporary file or folder; checked
with umask 022 (a colleague can read) and 077 (only the owner), for a model file, an exported
FMU and its parameter set, and a campaign folder (the folder, its runs and sidecars)."""

from __future__ import annotations

import os
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from feeddrive import cli
from feeddrive.data import sidecar_path
from feeddrive.experiments import campaign as campaign_mod
from feeddrive.experiments.campaign import write_campaign
from feeddrive.outputs import MARKER, output_dir
from feeddrive.paper import paper_parameters


@contextmanager
def umask(mask: int) -> Iterator[None]:
    old = os.umask(mask)
    try:
        yield
    finally:
        os.umask(old)


def _mode(p: Path) -> int:
    return stat.S_IMODE(p.stat().st_mode)


@pytest.mark.parametrize("mask", [0o022, 0o077])
def test_files_and_folders_follow_the_umask(tmp_path, mask, monkeypatch, fmu2_path, fmu3_path):
    real_plan = campaign_mod.plan
    monkeypatch.setattr(campaign_mod, "plan", lambda quick: real_plan(quick)[:1])  # one run
    file_mode, dir_mode = 0o666 & ~mask, 0o777 & ~mask
    with umask(mask):
        assert cli.main(["model", "--paper", "--out", str(tmp_path / "m.json")]) == 0
        assert cli.main(["fmu", str(tmp_path / "m.json"), "--out", str(tmp_path / "D.fmu")]) == 0
        with output_dir(tmp_path / "report") as stage:
            (stage / "sub").mkdir()
            (stage / "sub" / "a.txt").write_text("a")
        runs = write_campaign(tmp_path / "runs", model=paper_parameters(), quick=True)
    files = [
        tmp_path / "m.json",
        tmp_path / "D.fmu",
        tmp_path / "D.ssv",
        tmp_path / "report" / MARKER,
        tmp_path / "report" / "sub" / "a.txt",
        tmp_path / "runs" / MARKER,
        *runs,
        *(sidecar_path(r) for r in runs),
    ]
    for f in files:
        assert _mode(f) == file_mode, (f, oct(_mode(f)))
    for d in (tmp_path / "report", tmp_path / "report" / "sub", tmp_path / "runs"):
        assert _mode(d) == dir_mode, (d, oct(_mode(d)))
