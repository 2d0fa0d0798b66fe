"""The circular test's report: one polar plot per case (magnified radial deviation, as a
ballbar plot reads: the nominal circle, the CCW and CW traces, a scale in um/div) and the
table of G, H and the quadrant glitches, written as ``index.html`` with ``circle_*.png``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, cast

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.projections.polar import PolarAxes

from ..xy.circle_test import MIN_PER_M_S, CircleCase, circle_table
from .page import Page

DIVISIONS = 4  #: grid rings either side of the nominal circle
COLOURS = {"ccw": "tab:blue", "cw": "tab:red"}


def scale_um_per_div(cases_F_um: float) -> float:
    """A round scale (1, 2, 5 x 10^k um/div) that fits |F| within :data:`DIVISIONS` rings."""
    need = max(cases_F_um, 1e-3) / DIVISIONS
    k = np.floor(np.log10(need))
    for m in (1.0, 2.0, 5.0, 10.0):
        if m * 10**k >= need:
            return float(m * 10**k)
    return float(10 ** (k + 1))


def case_name(case: CircleCase) -> str:
    """File stem of a case's plot: circle_r10mm_F1mmin_gms."""
    return f"circle_r{case.radius * 1e3:g}mm_F{case.feed * 60:g}mmin_{case.feedforward}".replace(
        ".", "p"
    )


def polar_figure(case: CircleCase) -> plt.Figure:
    """The polar plot of one case: F about each direction's LSQ centre, magnified."""
    F_all = np.concatenate([r.trace.F for r in case.runs.values()]) * 1e6
    div = scale_um_per_div(float(np.max(np.abs(F_all))))
    span = DIVISIONS * div
    fig = plt.figure(figsize=(5.6, 5.6))
    ax = cast(PolarAxes, fig.add_subplot(projection="polar"))
    for d, r in case.runs.items():
        th = r.trace.theta
        o = np.argsort(th)
        F = r.trace.F[o] * 1e6
        ax.plot(
            np.append(th[o], th[o][0] + 2 * np.pi),
            np.append(F, F[0]),
            lw=1.0,
            color=COLOURS.get(d),
            label=f"{d.upper()}  G = {r.trace.G * 1e6:.1f} um",
        )
    ring = np.linspace(0, 2 * np.pi, 721)
    ax.plot(ring, np.zeros_like(ring), color="k", lw=1.2, label="nominal circle")
    ax.set_rorigin(-2.5 * span)
    ax.set_ylim(-span, span)
    ax.set_yticks(np.arange(-DIVISIONS, DIVISIONS + 1) * div)
    ax.set_yticklabels([])
    ax.set_xticks(np.deg2rad(np.arange(0, 360, 45)))
    H = "" if not np.isfinite(case.H) else f", H = {case.H * 1e6:.1f} um"
    ax.set_title(
        f"r = {case.radius * 1e3:g} mm, F = {case.feed * 60:.3g} m/min, "
        f"FF {case.feedforward}{H}\nradial deviation, {div:g} um/div",
        fontsize=9,
    )
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, -0.2), ncol=2, fontsize=8)
    return fig


def direction_rows(cases: Sequence[CircleCase]) -> list[dict[str, Any]]:
    """The table of every figure, one row per case and direction (narrow enough for a page):
    radius, feed, feedforward, direction, G, F max / min, the glitch at each quadrant change,
    the case's G_b and H, the run's wall time."""
    angles = sorted(
        {round(g.angle_deg) for c in cases for r in c.runs.values() for g in r.glitches}
    )
    rows = []
    for c in cases:
        for d, r in c.runs.items():
            row: dict[str, Any] = {
                "r [mm]": c.radius * 1e3,
                "feed [m/min]": c.feed * MIN_PER_M_S,
                "feedforward": c.feedforward,
                "direction": d,
                "G": r.trace.G * 1e6,
                "F max": r.trace.F_max * 1e6,
                "F min": r.trace.F_min * 1e6,
            }
            heights = {round(g.angle_deg): g.height * 1e6 for g in r.glitches}
            for a in angles:
                row[f"glitch {a}°"] = heights.get(a, "-")
            row["G_b"] = c.G_b * 1e6 if np.isfinite(c.G_b) else "-"
            row["H"] = c.H * 1e6 if np.isfinite(c.H) else "-"
            row["wall [s]"] = r.wall
            rows.append(row)
    return rows


def write_circle_report(
    cases: Sequence[CircleCase], out_dir: str | Path, axes_text: Sequence[str] = ()
) -> Path:
    """index.html and one polar plot per case in ``out_dir`` (a staged folder)."""
    page = Page(out_dir, "ISO 230-4 circular test on the X-Y table")
    page.text(
        "Two axes (each a plant FMU and a controller FMU) stepped by one master at Ts; "
        "radial deviation F about the least-squares centre of each direction's 360 deg "
        "at constant feed (the ramped start and stop are excluded). G: circular "
        "deviation; H: circular hysteresis (CW vs CCW about their common LSQ centre); "
        "glitch: quadrant reversal spike over the local baseline, + outwards."
    )
    page.lines(list(axes_text))
    page.pre(circle_table(cases))
    page.table(
        direction_rows(cases),
        caption="All figures: one row per case and direction "
        "(lengths in µm; G_b and H: both directions of the case)",
    )
    for c in cases:
        page.figure(
            polar_figure(c),
            case_name(c),
            caption=f"{case_name(c)}: magnified radial deviation, CCW blue, CW red",
        )
    return page.write()
