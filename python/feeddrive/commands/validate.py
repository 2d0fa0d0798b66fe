"""`feeddrive validate`: replay a measured run through model and controller and print the gap."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..validation.replay import validate_file
from .common import stages


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive validate`` with the parsed arguments ``a``; returns the exit status."""
    with stages("validate", a) as stage:
        rep = validate_file(Path(a.measured), Path(a.model) if a.model else None, stage)
    print(rep.text())
    return 0
