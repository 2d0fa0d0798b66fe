"""The diagnosis report: report.html with the residual plots, beside the diagnosis files.

``write_diagnosis(diag, out_dir)`` writes diagnosis.json, model.json (the confirmed effects),
model_all_fits.json (every fit) and model_stepK.json
(:func:`feeddrive.diagnose.output.write_files`) and then report.html with PNGs: the verdict
in one sentence at the top (with the hint when the residual is unexplained), which effects
are confirmed and why, the hints, the final residual per time block, the noise floor per run,
the residual of the start and final models against time, position and displacement since
reversal, the spatial spectrum of the starting residual, and one overlay per step: the
residual before and after against the noise band (+-1 and +-3 x the per-sample noise floor).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np

from ..diagnose.localise import displacement_since_reversal, spatial_spectrum
from ..diagnose.output import write_files
from ..diagnose.significance import NOISE_FACTOR
from ..diagnose.workflow import Diagnosis
from ..outputs import output_dir
from ..residual import RunResidual
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


def residual_figure(
    axis: Axis,
    before: list[RunResidual],
    after: list[RunResidual],
    title: str,
    xlabel: str,
    label_b: str = "before",
    label_a: str = "after",
    band: list[np.ndarray] | None = None,
    factor: float = NOISE_FACTOR,
) -> plt.Figure:
    """One panel per run: the residual before and after against ``axis``; with ``band``
    (per run, per-sample noise floor [N]) also +-band and +-``factor`` x band."""
    n = len(before)
    fig, axes = plt.subplots(n, 1, figsize=(9, 2.6 * n + 0.6), squeeze=False)
    for j, (qb, qa) in enumerate(zip(before, after, strict=True)):
        ax = axes[j, 0]
        xb, kw, log = axis(qb)
        if band is not None and not log and not kw:
            ok = qb.valid
            for f, alpha, lab in (
                (factor, 0.15, f"{factor:g} x noise floor"),
                (1.0, 0.3, "noise floor"),
            ):
                ax.fill_between(
                    xb[ok],
                    -f * band[j][ok],
                    f * band[j][ok],
                    color="grey",
                    alpha=alpha,
                    lw=0,
                    label=lab if j == 0 else None,
                )
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
    params = [
        f"{n} = {_fmt(p['value'])} {p['unit']} (was {_fmt(p['before'])})"
        for n, p in s["parameters"].items()
    ]
    ga, gb = s["gap_after"], s["gap_before"]
    ref = s.get("refinement")
    change = (
        [f"refinement: the model force changes by {_fmt(ref['force_change_rms_N'])} N rms"]
        if ref
        else []
    )
    return [
        [str(k)],
        [s["effect"], s["decision"], f"cannot be told from: {amb}", *change],
        [
            f"held-out improvement {_fmt(ev['heldout_improvement'])}, t = {_fmt(ev['t_blocks'])}, "
            f"blocks improved {ev['blocks_improved']}",
            f"explains {_fmt(ev['explained_force_N'])} N rms on held-out blocks "
            f"({_fmt(ev['x_noise_floor'])} x noise floor; threshold {_fmt(ev['threshold_N'])} N)",
            ev["variant"],
            f"where: {where}",
        ],
        params or ["-"],
        [
            f"{_fmt(gb['force_rms_N'])} N -> {_fmt(ga['force_rms_N'])} N "
            f"(held-out {_fmt(ga.get('force_rms_heldout_N'))} N)"
        ],
    ]


def _time_table(page: Page, ax: dict) -> None:
    """The final residual per time block of each run, and its trend."""
    rows = []
    for run, tab in ax.get("runs", {}).items():
        for b in tab["blocks"]:
            rows.append(
                {
                    "run": run,
                    "t [s]": f"{b['t_lo_s']:.2f}-{b['t_hi_s']:.2f}",
                    "rms [N]": b["rms_N"],
                    "noise floor [N]": b.get("floor_N"),
                    "excess [N]": b.get("excess_N"),
                    "run trend [N/s]": tab.get("trend_N_per_s"),
                }
            )
    if rows:
        page.table(
            rows,
            caption="time axis: the final residual per time block of each run "
            "(a drift or a warm-up shows as a trend)",
        )


def write_diagnosis(
    diag: Diagnosis,
    out_dir: str | Path,
    inputs: Iterable[str | Path | None] = (),
    force: bool = False,
) -> Path:
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
    page.text(f"Verdict: {doc['verdict']['sentence']}")
    loc = doc["verdict"].get("where")
    if loc:
        rows = [
            {
                "where": key,
                "regime": loc[key]["regime"],
                **{
                    k: v
                    for k, v in loc[key]["table"].get(loc[key]["regime"], {}).items()
                    if k != "n"
                },
            }
            for key in ("speed", "direction", "since_reversal")
        ]
        sb = loc["stroke_band"]
        rows.insert(
            0,
            {
                "where": "stroke band",
                "regime": f"{sb['x_lo_m'] * 1e3:.1f}-{sb['x_hi_m'] * 1e3:.1f} mm",
                **{
                    k: sb[k]
                    for k in ("rms_N", "floor_N", "excess_share", "sample_share", "concentration")
                    if k in sb
                },
            },
        )
        page.table(
            rows,
            caption="where the residual above the noise floor sits "
            "(concentration: share of the excess energy / share of samples)",
        )
    conf = doc["confirmation"]
    mj, ma = conf["model_json"], conf["model_all_fits_json"]
    page.lines(
        [
            f"Runs: {', '.join(doc['runs'])}. Start model: {doc['model_start']}.",
            f"model.json: {mj['name']}, the effects the diagnosis confirmed "
            f"({', '.join(mj['effects_added']) or 'none added'}; force gap "
            f"{_fmt(mj['gap_N'])} N). model_all_fits.json: {ma['name']}, every fit "
            f"({', '.join(ma['effects_added']) or 'none added'}; force gap "
            f"{_fmt(ma['gap_N'])} N).",
            f"Confirmed: {conf['rule']}.",
        ]
    )
    if conf["steps"]:
        page.table(
            [
                {
                    "effect": r["effect"],
                    "confirmed": r["confirmed"],
                    "where it acted": ", ".join(r["regimes"]),
                    "final residual there [N]": r.get("rms_final_N"),
                    "noise floor there [N]": r.get("floor_N"),
                    "excess [N]": r.get("excess_N"),
                    "threshold [N]": r["threshold_N"],
                    "why": r["why"],
                }
                for r in conf["steps"]
            ],
            caption="which fitted effects are confirmed (model.json) and which are only "
            "in model_all_fits.json",
        )
    if doc["verdict"].get("hints"):
        page.table(
            [
                {
                    "signature": h["signature"],
                    "explained force [N]": h["explained_force_N"],
                    "size": h["text"],
                }
                for h in doc["verdict"]["hints"]
            ],
            caption="signatures outside the catalogue fitted to the final residual "
            "(hints, never model changes; the best is in the verdict)",
        )
    _time_table(page, doc["localisation_final"].get("time", {}))
    page.lines(doc["notes"])
    nf, sig = doc["noise_floor"], doc["significance"]
    page.heading("Noise floor")
    names = list(nf["runs"])
    fields = list(dict.fromkeys(k for row in nf["runs"].values() for k in row))
    page.table(
        [{"quantity": k, **{n: nf["runs"][n].get(k, "-") for n in names}} for k in fields],
        caption="noise floor per run (a column each): position step, force noise, "
        "timing jitter and the force each leaves in the residual [N]",
    )
    ls, lf = doc["localisation_start"]["regimes"], doc["localisation_final"]["regimes"]
    page.table(
        [
            {
                "regime": k,
                "noise floor [N]": f,
                "start model [N]": ls.get(k, {}).get("rms"),
                "final model [N]": lf.get(k, {}).get("rms"),
            }
            for k, f in nf["regimes_rms_N"].items()
        ],
        caption="noise floor and residual per regime (rms)",
    )
    page.lines(
        [
            f"Overall noise floor {_fmt(nf['rms_N'])} N rms. A candidate is named only "
            f"when it explains at least {_fmt(sig['threshold_N'])} N rms on held-out "
            f"blocks: {_fmt(sig['noise_factor'])} x the floor "
            f"({_fmt(sig['noise_threshold_N'])} N) and {sig['practical_share']:.1%} of "
            f"the friction level {_fmt(sig['level_N'])} N ({sig['level_source']})."
        ]
    )
    page.heading("Steps")
    page.cells(
        ["#", "effect", "evidence", "parameters", "force gap (rms)"],
        [_step_row(k, s) for k, s in enumerate(doc["steps"], 1)],
    )
    page.lines([f"Stopped: {doc['stop'].get('reason')}"])
    page.heading("Plots")
    r0, r1 = diag.residual_start, diag.residual_final
    band = [f.sigma for f in diag.floors] if diag.floors else None
    for name, axis, xl, title in (
        ("residual_time", _vs_time, "time [s]", "force residual against time"),
        ("residual_position", _vs_position, "position [mm]", "force residual against position"),
        (
            "residual_reversal",
            _vs_dsr,
            "displacement since reversal [um]",
            "force residual against displacement since reversal",
        ),
    ):
        page.figure(
            residual_figure(
                axis,
                r0,
                r1,
                title + " (start model / final model)",
                xl,
                "start model",
                "final model",
                band=band,
            ),
            name,
            title,
            dpi=90,
        )
    page.figure(spectrum_figure(r0), "spectrum", "spatial spectrum", dpi=90)
    for k, st in enumerate(diag.steps, 1):
        page.figure(
            residual_figure(
                _vs_time,
                st.residual_before,
                st.residual_after,
                f"step {k}: {st.decision} {st.effect} - residual before / "
                "after against the noise band",
                "time [s]",
                band=band,
            ),
            f"step{k}_{st.effect}",
            f"step {k} overlay",
            dpi=90,
        )
    return page.write("report.html")
