"""`feeddrive circle`: the ISO 230-4 circular test on the X-Y table (G, H, glitches, polar plots)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..fmu import fmu_path
from ..harness.controller_fmu import controller_fmu_path
from ..outputs import output_dir
from ..report.circle import write_circle_report
from ..xy.circle_test import MIN_PER_M_S, check_fits, circle_table, circular_case
from ..xy.machine import xy_axes
from ..xy.system import circle_system, write_xy_osp
from .common import bar


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive circle`` with the parsed arguments ``a``; returns the exit status."""
    fmu_path()
    controller_fmu_path()  # no FMU: one line before the runs
    axes = xy_axes(a.x_model, a.y_model, a.mismatch)  # a bad model file: one line now
    radii = [r * 1e-3 for r in a.radius_mm]
    for r in radii:
        check_fits(axes, r)
    directions = list(dict.fromkeys(a.direction))
    combos = [
        (r, f, ff) for r in radii for f in a.feed_m_min for ff in dict.fromkeys(a.feedforward)
    ]
    with output_dir(Path(a.out), [a.x_model, a.y_model], a.force, what="circle") as stage:
        cases = [
            circular_case(axes, r, f / MIN_PER_M_S, ff, directions)
            for r, f, ff in bar(combos, "circle", "case", a)
        ]
        lines = [
            f"axis {ax.name}: {ax.source} (m = {ax.nominal['m']:g} kg); plant = nominal "
            + ("x Sec. 4 mismatch" if a.mismatch == "sec4" else "(no mismatch)")
            for ax in axes
        ]
        write_circle_report(cases, stage, lines)
        osp = (
            [
                write_xy_osp(sy, stage / "osp" / sy.name).parent.name
                for sy in (
                    circle_system(axes, c.radius, c.feed, d, c.feedforward)
                    for c in cases
                    for d in directions
                )
            ]
            if a.osp
            else []
        )
    print(circle_table(cases))
    print("\n".join(lines))
    print(f"wrote {Path(a.out) / 'index.html'} and {len(cases)} polar plots (circle_*.png)")
    if osp:
        print(
            f"wrote {len(osp)} OSP system structures for libcosim (4 FMUs each): "
            f"{Path(a.out) / 'osp' / osp[0] / 'OspSystemStructure.xml'}, ..."
        )
    return 0
