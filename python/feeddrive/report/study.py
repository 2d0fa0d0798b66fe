"""The report page of a parameter study: counts, sensitivity table, histograms of the
metrics, a scatter matrix of metrics against parameters and (one-at-a-time studies) the
tornado chart of the sensitivities; and the page of a bootstrap study (the interval table and
the identification's figures)."""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from ..study import OK, BootstrapStudyResult, StudyResult
from . import identification
from .page import Page


def _ok_column(res: StudyResult, col: str) -> np.ndarray:
    v = np.array([r[col] for r in res.rows if r["status"] == OK], dtype=float)
    return v[np.isfinite(v)]


def histograms(res: StudyResult) -> plt.Figure:
    """One histogram per metric over the runs that succeeded."""
    cols = res.study.metric_columns
    fig, axes = plt.subplots(1, len(cols), figsize=(3.6 * len(cols), 3.0), squeeze=False)
    for ax, c in zip(axes[0], cols, strict=True):
        v = _ok_column(res, c)
        if v.size:
            ax.hist(v, bins=min(30, max(5, int(math.sqrt(v.size)))), color="0.4")
        ax.set_xlabel(c)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("runs")
    fig.tight_layout()
    return fig


def scatter_matrix(res: StudyResult) -> plt.Figure:
    """Each metric (rows) against each parameter (columns), runs that succeeded."""
    ok = [r for r in res.rows if r["status"] == OK]
    ps, ms = res.study.parameter_names, res.study.metric_columns
    fig, axes = plt.subplots(
        len(ms),
        len(ps),
        figsize=(2.8 * len(ps), 2.4 * len(ms)),
        squeeze=False,
        sharex="col",
        sharey="row",
    )
    for i, m in enumerate(ms):
        for j, p in enumerate(ps):
            ax = axes[i][j]
            ax.plot([r[p] for r in ok], [r[m] for r in ok], ".", ms=3, color="k")
            ax.grid(alpha=0.3)
            if i == len(ms) - 1:
                ax.set_xlabel(p, fontsize=8)
            if j == 0:
                ax.set_ylabel(m, fontsize=8)
    fig.tight_layout()
    return fig


def tornado(res: StudyResult) -> plt.Figure:
    """Change of each metric with each parameter at its low / high end (largest on top)."""
    ms = res.study.metric_columns
    fig, axes = plt.subplots(
        1, len(ms), figsize=(4.2 * len(ms), 0.5 * len(res.study.parameters) + 1.6), squeeze=False
    )
    for ax, m in zip(axes[0], ms, strict=True):
        items = [s for s in res.sensitivities if s.metric == m][::-1]
        y = np.arange(len(items))
        ax.barh(y, [s.low for s in items], color="tab:blue", label="low end")
        ax.barh(y, [s.high for s in items], color="tab:red", alpha=0.7, label="high end")
        ax.set_yticks(y, [s.parameter for s in items], fontsize=8)
        ax.axvline(0, color="k", lw=0.8)
        ax.set_xlabel(f"change of {m}")
        ax.grid(alpha=0.3, axis="x")
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    return fig


def write_study_report(res: StudyResult, out: str | Path) -> Path:
    """Write ``out``/report.html (and its PNGs); returns its path."""
    page = Page(out, f"Parameter study: {res.study.name}")
    page.pre(res.summary())
    if res.failed:
        page.heading("Failed runs")
        page.table(
            [{"run": r["run"], "message": r["message"]} for r in res.rows if r["status"] != OK][
                :50
            ],
            caption="first 50",
        )
    if any(r["status"] == OK for r in res.rows):
        page.heading("Metrics")
        page.figure(histograms(res), "study_histograms", "metrics over the runs that succeeded")
        page.figure(scatter_matrix(res), "study_scatter", "metrics against parameters")
        if res.study.design["type"] == "oat":
            page.figure(
                tornado(res),
                "study_tornado",
                "one at a time: change of each metric from base at each end",
            )
    return page.write("report.html")


def write_bootstrap_report(res: BootstrapStudyResult, out: str | Path) -> Path:
    """Write ``out``/report.html for a bootstrap study: counts, the interval table and the
    identification's figures; returns its path."""
    page = Page(out, f"Identification bootstrap: {res.study.name}")
    page.pre(res.summary())
    identification.add_to_page(page, res.identification)
    return page.write("report.html")
