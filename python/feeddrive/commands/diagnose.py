"""`feeddrive diagnose`: name the effects the model lacks, write the diagnosis and its report."""

from __future__ import annotations

import argparse

from ..data import load_run, sidecar_path
from ..diagnose.workflow import diagnose
from ..harness.checked_runs import check_run
from ..model_file import load_model
from ..outputs import check_dir
from ..report.diagnosis import write_diagnosis
from .common import stages


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive diagnose`` with the parsed arguments ``a``; returns the exit status."""
    inputs = [a.model, *a.runs, *(sidecar_path(p) for p in a.runs)]
    check_dir(a.out, inputs, a.force)
    runs = [load_run(p) for p in a.runs]
    model = load_model(a.model)
    sides = [check_run(run, model) for run in runs]
    said = [
        line
        for run, s in zip(runs, sides, strict=True)
        if run.path is not None and (line := s.note_line(str(sidecar_path(run.path))))
    ]
    with stages("diagnose", a) as stage:
        diag = diagnose(
            runs,
            model,
            max_steps=a.max_steps,
            force_gain=a.force_gain,
            window=a.window,
            n_blocks=a.blocks,
            closed_loop=not a.no_closed_loop,
            notes=said,
            progress=stage,
        )
        stage("report")
        report = write_diagnosis(diag, a.out, inputs, a.force)
    for note in diag.notes:
        print(note)
    for k, s in enumerate(diag.steps, 1):
        amb = f" (cannot be told from {', '.join(s.ambiguous_with)})" if s.ambiguous_with else ""
        print(
            f"step {k}: {s.decision} {s.effect}{amb}: held-out improvement "
            f"{s.evidence['heldout_improvement']:.1%}, t = {s.evidence['t_blocks']:.1f}; "
            f"force gap (rms of the force residual) {s.gap_before['force_rms_N']:.3g} N -> "
            f"{s.gap_after['force_rms_N']:.3g} N"
        )
    print(f"stopped: {diag.stop.get('reason')}")
    print(f"verdict: {diag.verdict['verdict']}: {diag.verdict['sentence']}")
    for rec in diag.confirmation.get("steps", []):
        print(
            f"{rec['effect']}: {'confirmed' if rec['confirmed'] else 'not confirmed'}: {rec['why']}"
        )
    mj, ma = diag.confirmation["model_json"], diag.confirmation["model_all_fits_json"]
    print(
        f"model.json: the confirmed effects ({', '.join(mj['effects_added']) or 'none added'}), "
        f"force gap {mj['gap_N']:.3g} N; model_all_fits.json: every fit "
        f"({', '.join(ma['effects_added']) or 'none added'}), force gap {ma['gap_N']:.3g} N"
    )
    print(
        f"wrote {a.out / 'diagnosis.json'}, {a.out / 'model.json'}, "
        f"{a.out / 'model_all_fits.json'}, {report}"
    )
    return 0
