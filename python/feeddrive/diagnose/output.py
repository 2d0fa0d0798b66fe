"""Files of a diagnosis: diagnosis.json, model.json and report.html with PNG plots.

Schema of diagnosis.json: see the README, section "Discrepancy diagnosis".
"""
from __future__ import annotations

import html
import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..model_file import save_model
from .localise import displacement_since_reversal, spatial_spectrum
from .residual import RunResidual

if TYPE_CHECKING:
    from .workflow import Diagnosis


def _clean(obj: Any) -> Any:
    """JSON-safe copy: numpy scalars to Python, non-finite floats to None."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def diagnosis_json(diag: "Diagnosis") -> dict:
    """The JSON document of a diagnosis (README, "Discrepancy diagnosis")."""
    return _clean(diag.to_json())


def _plot_runs(ax_fn, before: list[RunResidual], after: list[RunResidual], path: Path,
               title: str, xlabel: str, label_b: str = "before", label_a: str = "after") -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(before)
    fig, axes = plt.subplots(n, 1, figsize=(9, 2.6 * n + 0.6), squeeze=False)
    for j, (qb, qa) in enumerate(zip(before, after)):
        ax = axes[j, 0]
        xb, kw, log = ax_fn(qb)
        ax.plot(xb[qb.valid], qb.r[qb.valid], lw=0.6, label=label_b, **kw)
        xa, kw, log = ax_fn(qa)
        ax.plot(xa[qa.valid], qa.r[qa.valid], lw=0.6, label=label_a, alpha=0.8, **kw)
        ax.set_ylabel(f"{qb.name}\nresidual [N]")
        ax.grid(alpha=0.3)
        if log:
            ax.set_xscale("log")
    axes[0, 0].set_title(title)
    axes[0, 0].legend(loc="upper right", fontsize=8)
    axes[-1, 0].set_xlabel(xlabel)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _vs_time(q):
    return q.time, {}, False


def _vs_position(q):
    return q.x * 1e3, {"marker": ".", "linestyle": "none", "ms": 1}, False


def _vs_dsr(q):
    d = np.maximum(displacement_since_reversal(q.x), 1e-8) * 1e6
    return d, {"marker": ".", "linestyle": "none", "ms": 1}, True


def _plot_spectrum(res: list[RunResidual], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

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
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.4g}"
    return html.escape(str(v))


def write_outputs(diag: "Diagnosis", out_dir: Path) -> None:
    """diagnosis.json, model.json and report.html (+ PNGs) in ``out_dir``."""
    out_dir.mkdir(parents=True, exist_ok=True)
    doc = diagnosis_json(diag)
    (out_dir / "diagnosis.json").write_text(json.dumps(doc, indent=2, allow_nan=False) + "\n",
                                            encoding="utf-8")
    save_model(diag.model, out_dir / "model.json")
    for k, st in enumerate(diag.steps, 1):
        if st.model_after is not None:
            save_model(st.model_after, out_dir / f"model_step{k}.json")
    figs: list[tuple[str, str]] = []
    r0, r1 = diag.residual_start, diag.residual_final
    for name, fn, xl, title in (
            ("residual_time.png", _vs_time, "time [s]", "force residual against time"),
            ("residual_position.png", _vs_position, "position [mm]",
             "force residual against position"),
            ("residual_reversal.png", _vs_dsr, "displacement since reversal [um]",
             "force residual against displacement since reversal")):
        _plot_runs(fn, r0, r1, out_dir / name, title + " (start model / final model)", xl,
                   "start model", "final model")
        figs.append((name, title))
    _plot_spectrum(r0, out_dir / "spectrum.png")
    figs.append(("spectrum.png", "spatial spectrum"))
    for k, st in enumerate(diag.steps, 1):
        name = f"step{k}_{st.effect}.png"
        _plot_runs(_vs_time, st.residual_before, st.residual_after, out_dir / name,
                   f"step {k}: {st.effect} - residual before / after", "time [s]")
        figs.append((name, f"step {k} overlay"))
    rows = []
    for k, s in enumerate(doc["steps"], 1):
        ev = s["evidence"]
        params = "<br>".join(f"{html.escape(n)} = {_fmt(p['value'])} {html.escape(p['unit'])}"
                             f" (was {_fmt(p['before'])})" for n, p in s["parameters"].items())
        where = ", ".join(w["regime"] for w in ev["where"])
        amb = ", ".join(s["ambiguous_with"]) or "-"
        rows.append(f"<tr><td>{k}</td><td><b>{s['effect']}</b><br>{s['decision']}; "
                    f"cannot be told from: {html.escape(amb)}</td>"
                    f"<td>held-out improvement {_fmt(ev['heldout_improvement'])}, "
                    f"t = {_fmt(ev['t_blocks'])}, blocks improved {ev['blocks_improved']}"
                    f"<br>{html.escape(ev['variant'])}<br>where: {html.escape(where)}</td>"
                    f"<td>{params}</td><td>{_fmt(s['gap_before']['force_rms_N'])} N &rarr; "
                    f"{_fmt(s['gap_after']['force_rms_N'])} N"
                    f" (held-out {_fmt(s['gap_after'].get('force_rms_heldout_N'))} N)</td></tr>")
    stop = doc["stop"]
    body = [
        "<!doctype html><html><head><meta charset='utf-8'><title>feeddrive diagnosis</title>",
        "<style>body{font-family:sans-serif;max-width:1000px;margin:auto}"
        "td,th{border:1px solid #ccc;padding:4px;vertical-align:top;font-size:13px}"
        "table{border-collapse:collapse}</style></head><body>",
        "<h1>Discrepancy diagnosis</h1>",
        f"<p>Runs: {html.escape(', '.join(doc['runs']))}. Start model: "
        f"{html.escape(doc['model_start'])}. Final model: {html.escape(doc['final_model'])} "
        "(model.json).</p>",
        "<p>" + "<br>".join(html.escape(n) for n in doc["notes"]) + "</p>",
        "<h2>Steps</h2><table><tr><th>#</th><th>effect</th><th>evidence</th>"
        "<th>parameters</th><th>force gap (rms)</th></tr>", *rows, "</table>",
        f"<p><b>Stopped:</b> {html.escape(str(stop.get('reason')))}</p>",
        "<h2>Plots</h2>",
        *[f"<h3>{html.escape(t)}</h3><img src='{n}' alt='{html.escape(t)}'>" for n, t in figs],
        "</body></html>"]
    (out_dir / "report.html").write_text("\n".join(body), encoding="utf-8")
