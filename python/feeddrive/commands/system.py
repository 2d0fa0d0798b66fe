"""`feeddrive system`: the closed loop written as SSP, OSP and container FMU (and run in the engines)."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

from ..fmu import fmu_path
from ..outputs import OutputError
from ..systems import sec3_system, sec4_system, write_all
from ..systems.compare import compare_engines
from .common import stages


def systems() -> dict[str, Callable]:
    """The closed loops ``feeddrive system --case`` writes, by name."""
    return {
        "sec3": sec3_system,
        "sec4_gms": lambda: sec4_system("gms"),
        "sec4_static": lambda: sec4_system("static"),
        "sec3_delay1": lambda: sec3_system(delay=1),
    }


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive system`` with the parsed arguments ``a``; returns the exit status."""
    fmu_path()
    system = systems()[a.case]()
    out = Path(a.out)
    there = [
        p
        for p in (
            out / f"{system.name}.ssp",
            out / f"{system.name}_osp",
            out / f"{system.name}_container.fmu",
        )
        if p.exists()
    ]
    if there and not a.force:
        raise OutputError(f"{there[0]}: exists; give --force to replace it, or another --out")
    with stages("system", a) as stage:
        stage("SSP, OSP, container FMU")
        files = write_all(system, out)
        if a.run:
            stage("libcosim and fmpy runs")
            compared = compare_engines(system, files)
    for kind, path in files.items():
        print(f"wrote {path} ({kind})")
    if a.run:
        print("\n".join(compared))
    return 0
