"""`feeddrive identify`: a model file identified from a folder of runs (optionally bootstrapped)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..identify.pipeline import identify_folder
from ..model_file import load_model
from ..study.bootstrap import bootstrap_folder
from .common import check_out_file, progress_enabled, stages


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive identify`` with the parsed arguments ``a``; returns the exit status."""
    if a.position_friction and a.bootstrap is not None:
        raise ValueError(
            "--position-friction is not available with --bootstrap "
            "(the bootstrap repeats the paper's steps 1-6)"
        )
    check_out_file(Path(a.out), [a.truth], a.force)
    truth = load_model(Path(a.truth)).fmu_parameters() if a.truth else None
    if a.bootstrap is None:
        with stages("identify", a) as stage:
            res = identify_folder(
                Path(a.runs),
                Path(a.out),
                truth=truth,
                position_friction=a.position_friction,
                progress=stage,
            )
        print(res.text())
        return 0
    res, boot = bootstrap_folder(
        Path(a.runs),
        Path(a.out),
        a.bootstrap,
        seed=a.seed,
        level=a.level,
        truth=truth,
        scheduler=a.scheduler,
        workers=a.workers,
        parallel=not a.serial,
        progress=progress_enabled(a),
        method=a.interval_method,
    )
    print(res.text())
    print(boot.text())
    return 0
