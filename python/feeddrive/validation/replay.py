"""`feeddrive validate`: replay a measured run's reference through the model and controller and
report the gap (position error at reversals and elsewhere; force residual along the measured
trajectory)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..data import DataError, Run, load_run
from ..experiments.tracking_error import ErrorSummary, reversal_mask, summarise
from ..harness.checked_runs import check_run
from ..harness.runs import replay
from ..harness.sidecar import Sidecar, read_sidecar
from ..model_file import ModelFile, load_model, paper_model
from ..residual import force_residual


@dataclass
class ValidationReport:
    run: Run
    model_name: str
    position: ErrorSummary | None
    force: dict[str, float] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    x_sim: np.ndarray | None = None

    def text(self) -> str:
        lines = [f"validate {self.run.path or self.run.name} against model '{self.model_name}'"]
        lines += [f"  note: {n}" for n in self.notes]
        if self.position is not None:
            p = self.position
            lines.append(
                "  position gap x_sim - x_meas (simulated minus measured position, after "
                "the first 0.5 s):"
            )
            lines.append(
                "    reversal peak (largest |gap| within 0.25 s of a reversal of x_ref): "
                + _um(p.reversal_peak, "no reversal of x_ref after the first 0.5 s")
            )
            lines.append(
                "    elsewhere max: "
                + _um(p.band, "every sample after the first 0.5 s is near a reversal")
            )
            lines.append("    rms: " + _um(p.rms, "the run is no longer than 0.5 s"))
        if self.force:
            lines.append(
                "  force residual K_f(x) i - m a - F_cg(x) - F_f - F_load (the force the "
                "model does not explain) [N]: "
                + ", ".join(f"{k} {v:.3f}" for k, v in self.force.items())
            )
        return "\n".join(lines)


def _um(value: float, missing: str) -> str:
    """A length [m] in µm, or why it is missing."""
    return f"{value * 1e6:.2f} µm" if math.isfinite(value) else f"not computed: {missing}"


def force_residual_summary(run: Run, model: ModelFile) -> tuple[dict[str, float], list[str]]:
    """rms/peak of the force residual along the measured trajectory, near reversals and elsewhere."""
    fr = force_residual(run, model)
    r = np.asarray(fr.r)
    notes = [] if run.has_current else [f"no measured current: motor force from {fr.force_source}"]
    valid = np.asarray(fr.valid, bool)
    lost = np.flatnonzero(valid & ~np.isfinite(r))
    if lost.size:  # never an answer from the samples that happen to stay finite
        raise DataError(
            run.path or run.name,
            int(lost[0]) + 2,
            None,
            f"the force residual is not finite on {lost.size} of {valid.sum()} "
            "samples (values too large for the model)",
        )
    ok = np.isfinite(r) & valid
    if not ok.any():
        raise DataError(
            run.path or run.name,
            None,
            None,
            "no sample where the force "
            "residual can be computed (run shorter than the acceleration window?)",
        )
    out = {"rms": float(np.sqrt(np.mean(r[ok] ** 2))), "peak": float(np.abs(r[ok]).max())}
    if run.x_ref is not None:
        near, far = reversal_mask(run.x_ref, run.Ts)
        if (near & ok).any():
            out["rms near reversals"] = float(np.sqrt(np.mean(r[near & ok] ** 2)))
        if (far & ok).any():
            out["rms elsewhere"] = float(np.sqrt(np.mean(r[far & ok] ** 2)))
    return out, notes


def validate(
    run: Run,
    model: ModelFile,
    side: Sidecar | None = None,
    progress: Callable[[str], None] | None = None,
) -> ValidationReport:
    """Replay ``run`` (closed loop when its sidecar names a controller the registry builds)
    and compute the gap.

    The replay (:func:`feeddrive.harness.runs.replay`) reads the position as the run's
    scale did (``sensors.quantum`` of the sidecar) without noise: the model's prediction.
    ``side`` is the run's sidecar as :func:`~feeddrive.harness.checked_runs.check_run` read
    it (default: read here); what it ignored and what could not be done without it are in
    the report's notes.
    ``progress`` is called with each stage's name as it starts (a progress bar).
    """
    stage = progress or (lambda name: None)
    notes: list[str] = []
    pos = None
    x_sim = None
    if side is None:
        side = read_sidecar(run.meta, where=f"{run.path or run.name}: sidecar", run=run)
    line = side.note_line("sidecar")
    if line:
        notes.append(line)
    if side.controller is not None and run.x_ref is not None:
        Ts = side.Ts if side.Ts is not None else run.Ts
        stage("closed-loop replay")
        x_sim = replay(model.fmu_parameters(), run, side)
        pos = summarise(x_sim - run.x, run.x_ref, Ts)
    elif side.foreign_controller is not None:
        notes.append(
            "closed-loop position gap not computed: the sidecar's controller is not "
            "one the registry builds (see above); only the force residual"
        )
    else:
        notes.append(
            "no controller in the run's sidecar (or no x_ref): the closed-loop position gap "
            "is not computed; only the force residual"
        )
    stage("force residual")
    force, fnotes = force_residual_summary(run, model)
    notes += fnotes
    return ValidationReport(
        run=run, model_name=model.name, position=pos, force=force, notes=notes, x_sim=x_sim
    )


def validate_file(
    measured: Path, model_path: Path | None = None, progress: Callable[[str], None] | None = None
) -> ValidationReport:
    """CLI entry: load the run and the model file (default: the paper's model)."""
    if progress is not None:
        progress("load")
    run = load_run(measured)
    model = load_model(model_path) if model_path else paper_model()
    side = check_run(run, model)
    return validate(run, model, side, progress)
