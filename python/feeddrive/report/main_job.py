"""The main job (`make run`, `feeddrive run` / `feeddrive report`): the paper's reproductions
and the controller design (:func:`feeddrive.experiments.reproduction.reproduce_paper`) written
as the HTML report with its figures and tables."""

from __future__ import annotations

import time
from pathlib import Path

from tqdm import tqdm

from ..experiments.reproduction import reproduce_paper
from ..outputs import output_dir
from ..realdata.odrive import analyse, findings_text
from . import closed_loop_figures as figs
from .identification import identification_section
from .page import Page

ODRIVE = Path("realdata") / "odrive-cogging"  # inside the shared data folder


def main_job(
    out_dir: Path,
    print_tables: bool = True,
    runs_dir: Path | None = None,
    shared_dir: Path | None = None,
    force: bool = False,
    progress: bool | None = None,
) -> dict:
    """Run Secs. 3 and 4, write ``out_dir/index.html``; return the tables' rows.

    With ``runs_dir`` (a folder of identification runs, e.g. from ``feeddrive experiments``)
    the page also gets the identification figures (Figs. 5-13 analogues); when the ODrive
    measured data sit in ``shared_dir/realdata/odrive-cogging``, their position-spectrum findings
    are added (else the page says why the section was skipped).

    ``out_dir`` is checked first and written whole at the end (it then holds this report
    only: :func:`feeddrive.outputs.output_dir`; a non-empty folder we did not write, or one
    holding ``runs_dir``, is refused unless ``force``).  ``progress``: a bar of the stages on
    stderr (None: when ``print_tables`` and stderr is a terminal)."""
    out_dir = Path(out_dir)
    with output_dir(out_dir, (runs_dir, shared_dir), force, what="report") as stage:
        return _main_job(stage, out_dir, print_tables, runs_dir, shared_dir, progress)


def _main_job(
    out_dir: Path,
    final_dir: Path,
    print_tables: bool,
    runs_dir: Path | None,
    shared_dir: Path | None,
    progress: bool | None,
) -> dict:
    """:func:`main_job` writing into ``out_dir`` (moved to ``final_dir`` afterwards)."""
    page = Page(out_dir, "feeddrive: the linear-motor feed drive of Villegas et al. (2014)")
    t0 = time.perf_counter()
    steps = tqdm(
        total=3,
        desc="feeddrive run",
        unit="stage",
        disable=(None if print_tables else True) if progress is None else not progress,
    )
    rep = reproduce_paper(out_dir, lambda: steps.update(1))
    design, run_line, r3, r4 = rep.design, rep.run_line, rep.sec3, rep.sec4
    steps.close()
    page.pre(run_line)
    page.heading(
        "Controller (state feedback, integral action, current estimator; ZPETC pre-filter)"
    )
    page.pre(design)
    page.heading("Sec. 3: simulation against measurement (30 mm, 6 s sinusoid)")
    page.text(
        "The 'measurement' is the full model with sensor effects (100 nm position quantisation, "
        "5 mA rms current noise acting on the stage, seed 3), written as sec3_measured.csv "
        "(the recording format of docs/data-format.md, sidecar JSON with the controller)."
    )
    page.table(r3.rows, "top-reversal peak and rms of x_sim - x_meas [um]")
    page.figure(
        figs.fig14(r3),
        "fig14_top_reversal",
        "Analogue of Fig. 14: top reversal, measured vs simulated",
    )
    page.figure(figs.sim_minus_measured(r3), "sec3_error", "x_sim - x_meas over the run")
    page.heading("Sec. 4: feedforward (5 mm, 6 s sinusoid, two periods)")
    page.pre(r4.table())
    page.table(r4.rows, "tracking error e = x_ref - x [um] beside the paper's values")
    page.figure(
        figs.fig16(r4),
        "fig16_feedforward",
        "Analogue of Fig. 16: tracking error for each feedforward",
    )
    page.figure(figs.reversal_closeups(r4), "sec4_reversals", "Error at each reference reversal")
    if runs_dir is not None:
        page.heading("Identification (Secs. 2.2-2.4) from " + str(runs_dir))
        identification_section(page, Path(runs_dir))
    page.heading("Real data: ODrive BLDC cogging maps (position spectrum)")
    odrive = Path(shared_dir) / ODRIVE if shared_dir is not None else None
    skipped = (
        "skipped: no shared data folder given (feeddrive run --shared DIR or $FEEDDRIVE_SHARED)"
        if odrive is None
        else None
        if odrive.is_dir()
        else f"skipped: {odrive} is not a folder"
    )
    if skipped is not None:
        page.text(skipped)
    elif odrive is not None:
        page.pre(findings_text(analyse(odrive)))
    path = final_dir / page.write().name
    wall = time.perf_counter() - t0
    if print_tables:
        print(design)
        print()
        print(run_line)
        print()
        print(r3.table())
        print()
        print(r4.table())
        print()
        if skipped is not None:
            print(f"ODrive real-data section {skipped}")
        print(f"report: {path}  (wall {wall:.1f} s)")
    return {"sec3": r3.rows, "sec4": r4.rows, "report": str(path)}
