"""`feeddrive experiments`: the identification experiments written as virtual runs."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..experiments.campaign import write_campaign
from .common import progress_enabled


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive experiments`` with the parsed arguments ``a``; returns the exit status."""
    paths = write_campaign(
        Path(a.out),
        model=Path(a.model) if a.model else None,
        seed=a.seed,
        force=a.force,
        repeats=a.repeats,
        progress=progress_enabled(a),
        fmt=a.format,
    )
    print(f"wrote {len(paths)} runs to {a.out}")
    return 0
