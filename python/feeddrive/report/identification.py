"""The identification's report section: the summary, the truth table, the intervals, the
effects' table and every figure (:mod:`.identification_figures`).

:func:`add_to_page` puts the text, the truth table and every figure on a report page;
:func:`identification_section` first identifies a folder (or list) of runs and, when the
true model is known, adds the Sec. 4 scenario simulated with the identified versus the true
plant (:func:`~.identification_figures.fig_sec4_comparison`); :func:`identification_page`
writes the page of ``feeddrive report``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, cast

import matplotlib.pyplot as plt

from ..data import Run
from ..effects import EFFECTS, report_figures, resolve
from ..identify.pipeline import identify_folder, identify_runs
from ..identify.result import IdentificationResult
from ..identify.sec4_check import REVERSAL_TOL, compare_sec4
from ..model_file import save_model
from ..outputs import Reads, output_dir
from .identification_figures import (
    fig6_dstft_cogging,
    fig7_cogging_components,
    fig8_dstft_ripple,
    fig9_ripple_components,
    fig_sec4_comparison,
    truth_parameters,
)
from .page import Page

#: (function, file stem, caption, step attribute) in page order: the figures the effects
#: declare (:func:`feeddrive.effects.report_figures`), each shown when its effect's step ran.
FIGURES: tuple[tuple[Callable[[IdentificationResult], plt.Figure], str, str, str], ...] = tuple(
    (
        cast(Callable[[IdentificationResult], plt.Figure], resolve(f.figure)),
        f.stem,
        f.caption,
        e.identification.step,
    )
    for e, f in report_figures()
)


#: How each interval method (the model file's ``uncertainty[...]["method"]``) is named in
#: the interval table.
INTERVAL_METHODS = {"parametric": "parametric, bias-corrected", "runs": "runs, percentile"}
#: What stands behind each method's intervals (the table's caption).
INTERVAL_EVIDENCE = {
    "parametric": "parametric: every run simulated again on the identified model with the "
    "measured noise and identified again; interval = estimate - bias +- "
    "t s sqrt(1 + 1/B) over the B replicates (the bias column is the b "
    "subtracted). Its coverage over 20 campaigns made by the FMU, per parameter, "
    "is in docs/intervals.md (Coverage); the current loop's coefficients are "
    "conditional on the order/delay the estimate chose.",
    "runs": "runs: percentiles over whole runs resampled within cells of repeats: the noise "
    "spread only, without the method's bias (their coverage of the Stribeck "
    "parameters over FMU campaigns is in docs/intervals.md: far below the level).",
}


def uncertainty_rows(res: IdentificationResult) -> list[dict[str, Any]]:
    """One row per parameter with an interval: value, lo, hi, level, the method, the
    replicates, the bias the interval corrects (parametric) (and the truth and whether the
    interval holds it, when known)."""
    truth = truth_parameters(res)
    rows = []
    for name, iv in res.model.uncertainty.items():
        row: dict[str, Any] = {
            "parameter": name,
            "value": res.model.parameters[name],
            "lo": iv["lo"],
            "hi": iv["hi"],
            "level": iv["level"],
            "method": INTERVAL_METHODS.get(iv.get("method", "runs"), "?"),
            "replicates": iv["replicates"],
            "bias corrected": iv.get("bias", "not estimated"),
        }
        if truth is not None:
            row["true"] = truth[name]
            row["true inside"] = "yes" if iv["lo"] <= truth[name] <= iv["hi"] else "no"
        rows.append(row)
    return rows


def effect_rows(res: IdentificationResult) -> list[dict[str, Any]]:
    """One row per effect of the catalogue (the registry :data:`feeddrive.effects.EFFECTS`):
    on in the identified model, the pipeline step that fits it and whether it ran, how it is
    identified, and what of this report shows it."""
    rows = []
    for e in EFFECTS:
        step = e.identification.step
        if not step:
            done = "no step of its own"
        else:
            done = f"{step}: " + ("fitted" if getattr(res, step) is not None else "not fitted")
        rows.append(
            {
                "effect": e.id,
                "on": "yes" if res.model.effects[e.id] else "no",
                "step": done,
                "identified by": e.identification.how,
                "shown by": "; ".join(e.report) or "-",
            }
        )
    return rows


def add_to_page(page: Page, results: IdentificationResult, level: int = 2) -> list[Path]:
    """Add the identification (summary text, truth table, the effects' table, every figure)
    to a report Page.

    Figures of steps that did not run are left out (the text says why).  Returns the PNGs.
    """
    page.heading("Identification (Secs. 2.2-2.4) from a folder of runs", level)
    page.pre(results.text() if not results.table else results.text().split("\n\n")[0])
    if results.table:
        page.table(
            [r.as_dict() for r in results.table],
            f"true ({results.truth.name if results.truth else 'truth'}) vs identified "
            "(error: relative, rms/range, or factor for C; see tolerance)",
            digits=5,
        )
    if results.model.uncertainty:
        methods = {iv.get("method", "runs") for iv in results.model.uncertainty.values()}
        page.table(
            uncertainty_rows(results),
            "bootstrap intervals of the identified parameters: "
            + " ".join(INTERVAL_EVIDENCE[m] for m in sorted(methods)),
            digits=6,
        )
    page.table(
        effect_rows(results),
        "the effects of the catalogue in the identified model "
        "(steps that did not run: the summary above says why)",
    )
    paths = []
    for fn, stem, caption, attr in FIGURES:
        if getattr(results, attr) is None:
            continue
        if (
            fn
            in (
                fig6_dstft_cogging,
                fig8_dstft_ripple,
                fig7_cogging_components,
                fig9_ripple_components,
            )
            and results.maps is not None
            and len(results.maps.samples.x) < 750
        ):
            continue  # the DSTFT needs a 75 mm stretch of map
        paths.append(page.figure(fn(results), stem, caption))
    return paths


def identification_section(
    page: Page,
    runs: str | Path | Sequence[Run] | IdentificationResult,
    truth: Any = None,
    out: str | Path | None = None,
    sec4: bool = True,
) -> IdentificationResult:
    """Identify a folder (or list) of runs and add the section to ``page``.

    Parameters
    ----------
    page : a :class:`feeddrive.report.Page`.
    runs : a folder of runs, a list of Runs, or an already computed result.
    truth : the model the runs came from, when known (adds the truth table and, with
        ``sec4``, the Sec. 4 scenario simulated with the identified versus the true plant).
    out : where to write the identified model file (optional).
    """
    if isinstance(runs, IdentificationResult):
        res = runs
    elif isinstance(runs, (str, Path)):
        res = identify_folder(runs, out, truth=truth)
    else:
        res = identify_runs(list(runs), truth=truth)
        if out is not None:
            save_model(res.model, out)
            res.out_path = Path(out)
    add_to_page(page, res)
    if sec4 and res.truth is not None:
        cmp = compare_sec4(res.model.fmu_parameters(), res.truth.fmu_parameters())
        page.heading("Sec. 4 scenario: identified model versus truth", 3)
        page.text(
            "Controller and feedforward designed on the identified model; the same loop "
            "simulated with the true model as plant (the machine) and with the identified "
            f"one (the prediction). Criterion: reversal peaks within {REVERSAL_TOL * 1e6:g} "
            f"um in every case: {'met' if cmp.ok else 'NOT met'}."
        )
        page.table(cmp.rows, "reversal peaks of the tracking error [um]")
        page.figure(
            fig_sec4_comparison(cmp),
            "id_sec4_comparison",
            "Sec. 4 tracking error: true plant vs identified plant",
        )
    return res


def identification_page(
    runs_dir: str | Path,
    out_dir: str | Path,
    truth: Any = None,
    force: bool = False,
    progress: Callable[[str], None] | None = None,
) -> tuple[Path, IdentificationResult]:
    """Identify the runs of ``runs_dir`` and write the identification report into ``out_dir``:
    ``index.html`` with every figure, and ``model.json`` (the identified model).

    ``out_dir`` is checked first and written whole at the end
    (:func:`feeddrive.outputs.output_dir`: a non-empty folder feeddrive did not write is
    refused unless ``force``).  ``truth``: the model the runs came from (a
    :class:`~feeddrive.model_file.ModelFile`), when known.  ``progress`` is called with each
    step's name.  Returns the page's path and the result.
    """
    out_dir = Path(out_dir)
    reads = Reads.of(run_folders=[runs_dir])
    with output_dir(out_dir, reads, force, what="identification") as stage:
        res = identify_folder(runs_dir, stage / "model.json", truth=truth, progress=progress)
        res.out_path = out_dir / "model.json"  # where it is once the folder is in place
        page = Page(stage, f"feeddrive: identification from {runs_dir}")
        if progress is not None:
            progress("figures")
        identification_section(page, res, sec4=truth is not None)
        page.write()
    return out_dir / "index.html", res
