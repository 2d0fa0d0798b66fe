"""`feeddrive report`: the identification report of a folder of runs (no reproductions)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..model_file import load_model
from ..report.identification import identification_page
from .common import stages


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive report`` with the parsed arguments ``a``; returns the exit status."""
    truth = load_model(Path(a.truth)) if a.truth else None
    with stages("report", a) as stage:
        page, res = identification_page(
            Path(a.runs), Path(a.out), truth=truth, force=a.force, progress=stage
        )
    print(res.text())
    print(
        f"wrote {page} (figures: {len(list(Path(a.out).glob('*.png')))} PNG) and "
        f"{Path(a.out) / 'model.json'} (the identified model)"
    )
    return 0
