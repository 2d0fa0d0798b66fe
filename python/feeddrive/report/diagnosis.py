"""The diagnosis report: report.html with the residual plots, beside the diagnosis files.

``write_diagnosis(diag, out_dir)`` writes diagnosis.json, model.json and model_stepK.json
(:func:`feeddrive.diagnose.output.write_files`) and then report.html with PNGs: the residual
of the start and final models against time, position and displacement since reversal, the
spatial spectrum of the starting residual, and one overlay per step.
"""
from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np

from ..diagnose.localise import displacement_since_reversal, spatial_spectrum
from ..diagnose.output import write_files
from ..diagnose.residual import RunResidual
from ..diagnose.workflow import Diagnosis
from ..outputs import output_dir
from .page import Page

#: How a residual is plotted: x values, line style, log x axis.
Axis = Callable[[RunResidual], tuple[np.ndarray, dict, bool]]


def _vs_time(q: RunResidual) -> tuple[np.ndarray, dict, bool]:
    return q.time, {}, False


def _vs_position(q: RunResidual) -> tuple[np.ndarray, dict, bool]:
    return q.x * 1e3, {"marker": ".", "linestyle": "none", "ms": 1}, False


def _vs_dsr(q: RunResidual) -> tuple[np.ndarray, dict, bool]:
    d = np.maximum(displacement_since_reversal(q.x), 1e-8) * 1e6
    return d, {"marker": ".", "linestyle": "none", "ms": 1}, True


def residual_figure(axis: Axis, before: list[RunResidual], after: list[RunResidual],
                    title: str, xlabel: str, label_b: str = "before",
                    label_a: str = "after") -> plt.Figure:
    """One panel per run: the residual before and after against ``axis``."""
    n = len(before)
    fig, axes = plt.subplots(n, 1, figsize=(9, 2.6 * n + 0.6), squeeze=False)
    for j, (qb, qa) in enumerate(zip(before, after)):
        ax = axes[j, 0]
        xb, kw, log = axis(qb)
        ax.plot(xb[qb.valid], qb.r[qb.valid], lw=0.6, label=label_b, **kw)
        xa, kw, log = axis(qa)
        ax.plot(xa[qa.valid], qa.r[qa.valid], lw=0.6, label=label_a, alpha=0.8, **kw)
        ax.set_ylabel(f"{qb.name}\nresidual [N]")
        ax.grid(alpha=0.3)
        if log:
            ax.set_xscale("log")
    axes[0, 0].set_title(title)
    axes[0, 0].legend(loc="upper right", fontsize=8)
    axes[-1, 0].set_xlabel(xlabel)
    fig.tight_layout()
    return fig


def spectrum_figure(res: list[RunResidual]) -> plt.Figure:
    """Spatial spectrum of a residual, unweighted (cogging-like) and per ampere (ripple-like)."""
    fig, ax = plt.subplots(figsize=(9, 3))
    for weight, lab in ((None, "cogging-like [N]"), ("i", "ripple-like [N/A]")):
        lams, amps = spatial_spectrum(res, weight=weight)
        if lams.size:
            ax.semilogx(lams * 1e3, amps, label=lab)
    ax.set_xlabel("wavelength along the stroke [mm]")
    ax.set_ylabel("amplitude")
    ax.set_title("spatial spectrum of the starting residual")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def _fmt(v: Any) -> str:
    return f"{v:.4g}" if isinstance(v, float) else str(v)


def _step_row(k: int, s: dict) -> list[list[str]]:
    ev = s["evidence"]
    where = ", ".join(w["regime"] for w in ev["where"])
    amb = ", ".join(s["ambiguous_with"]) or "-"
    params = [f"{n} = {_fmt(p['value'])} {p['unit']} (was {_fmt(p['before'])})"
              for n, p in s["parameters"].items()]
    ga, gb = s["gap_after"], s["gap_before"]
    return [[str(k)],
            [s["effect"], f"{s['decision']}; cannot be told from: {amb}"],
            [f"held-out improvement {_fmt(ev['heldout_improvement'])}, t = {_fmt(ev['t_blocks'])}, "
             f"blocks improved {ev['blocks_improved']}", ev["variant"], f"where: {where}"],
            params or ["-"],
            [f"{_fmt(gb['force_rms_N'])} N -> {_fmt(ga['force_rms_N'])} N "
             f"(held-out {_fmt(ga.get('force_rms_heldout_N'))} N)"]]


def write_diagnosis(diag: Diagnosis, out_dir: str | Path,
                    inputs: Iterable[str | Path | None] = (), force: bool = False) -> Path:
    """diagnosis.json, model.json (+ one per step) and report.html with PNGs in ``out_dir``;
    returns the path of report.html.

    The folder then holds this diagnosis only (written beside it, moved into place:
    :func:`feeddrive.outputs.output_dir`); it may not hold one of ``inputs`` (the runs, the
    start model); a non-empty folder we did not write is refused unless ``force``.
    """
    with output_dir(out_dir, inputs, force, what="diagnosis") as stage:
        _write_diagnosis(diag, stage)
    return Path(out_dir) / "report.html"


def _write_diagnosis(diag: Diagnosis, out: Path) -> Path:
    doc = write_files(diag, out)
    page = Page(out, "Discrepancy diagnosis")
    page.lines([f"Runs: {', '.join(doc['runs'])}. Start model: {doc['model_start']}. "
                f"Final model: {doc['final_model']} (model.json)."])
    page.lines(doc["notes"])
    page.heading("Steps")
    page.cells(["#", "effect", "evidence", "parameters", "force gap (rms)"],
               [_step_row(k, s) for k, s in enumerate(doc["steps"], 1)])
    page.lines([f"Stopped: {doc['stop'].get('reason')}"])
    page.heading("Plots")
    r0, r1 = diag.residual_start, diag.residual_final
    for name, axis, xl, title in (
            ("residual_time", _vs_time, "time [s]", "force residual against time"),
            ("residual_position", _vs_position, "position [mm]", "force residual against position"),
            ("residual_reversal", _vs_dsr, "displacement since reversal [um]",
             "force residual against displacement since reversal")):
        page.figure(residual_figure(axis, r0, r1, title + " (start model / final model)", xl,
                                    "start model", "final model"), name, title, dpi=90)
    page.figure(spectrum_figure(r0), "spectrum", "spatial spectrum", dpi=90)
    for k, st in enumerate(diag.steps, 1):
        page.figure(residual_figure(_vs_time, st.residual_before, st.residual_after,
                                    f"step {k}: {st.effect} - residual before / after", "time [s]"),
                    f"step{k}_{st.effect}", f"step {k} overlay", dpi=90)
    return page.write("report.html")
