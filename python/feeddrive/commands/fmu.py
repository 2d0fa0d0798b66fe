"""`feeddrive fmu`: a model file written as its own plant FMU and an SSP parameter set."""

from __future__ import annotations

import argparse

from ..export_fmu import fmu_command


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive fmu`` with the parsed arguments ``a``; returns the exit status."""
    print(fmu_command(a.model, a.out, a.fmi, a.force))
    return 0
