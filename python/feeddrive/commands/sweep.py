"""`feeddrive sweep`: a parameter study (or a bootstrap study) on Dask, its table and report."""

from __future__ import annotations

import argparse
import shutil
import sys
from pathlib import Path

from ..outputs import check_dir
from ..report.study import write_bootstrap_report, write_study_report
from ..study import BootstrapStudy, load_study_file, run_bootstrap_study, run_study, study_reads
from ..study.table import CSV_NAME, IDENTITY_NAME
from .common import UsageError, progress_enabled


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive sweep`` with the parsed arguments ``a``; returns the exit status."""
    study = load_study_file(a.study)
    if a.force and a.resume:
        raise UsageError(
            "give one of --force (start again, replacing --out) and --resume "
            "(keep the finished rows)"
        )
    if isinstance(study, BootstrapStudy):
        if a.resume:
            raise UsageError(
                f"--resume: {a.study} is a bootstrap study (kind 'bootstrap'), written "
                "whole at the end; run it again without --resume"
            )
        boot = run_bootstrap_study(
            study,
            a.out,
            scheduler=a.scheduler,
            workers=a.workers,
            parallel=not a.serial,
            progress=progress_enabled(a),
            force=a.force,
        )
        report = write_bootstrap_report(boot, a.out)
        print(boot.summary())
        print(f"wrote {report}")
        return 0
    out = Path(a.out)
    if a.force and out.exists():
        check_dir(out, study_reads(a.study), force=True)
        shutil.rmtree(out)
    elif (
        out.is_dir()
        and any(out.iterdir())
        and not any((out / n).exists() for n in (CSV_NAME, IDENTITY_NAME))
    ):
        raise UsageError(
            f"{out}: is a non-empty folder without a study's results; give --force "
            "to replace it, or another --out"
        )
    try:
        res = run_study(
            study,
            a.out,
            scheduler=a.scheduler,
            workers=a.workers,
            resume=a.resume,
            progress=progress_enabled(a),
            parallel=not a.serial,
        )
    except KeyboardInterrupt:
        print(
            f"feeddrive sweep: interrupted; the finished runs are in {a.out / 'results.csv'}: "
            f"run again with --resume",
            file=sys.stderr,
        )
        return 130
    report = write_study_report(res, a.out)
    print(res.summary())
    print(f"wrote {report}")
    return 0
