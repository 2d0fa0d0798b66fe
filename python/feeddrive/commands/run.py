"""`feeddrive run`: the main job (the paper's Secs. 3 and 4 reproduced, the report written, its tables printed)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..data import load_runs
from ..fmu import fmu_path
from ..harness.checked_runs import check_run
from ..outputs import check_dir
from ..report.main_job import main_job
from .common import progress_enabled


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive run`` with the parsed arguments ``a``; returns the exit status."""
    fmu_path()  # no FMU: one line before the job starts
    check_dir(Path(a.out), [a.runs, a.shared], a.force)
    for run in load_runs(a.runs) if a.runs else ():
        check_run(run)  # a bad run: one line now, not after the reproductions
    main_job(
        Path(a.out),
        print_tables=True,
        runs_dir=Path(a.runs) if a.runs else None,
        shared_dir=Path(a.shared) if a.shared else None,
        force=a.force,
        progress=progress_enabled(a),
    )
    return 0
