"""The checks every command applies to a measured run before any work, with the loader that
applies them to a folder of runs: :func:`check_run` (plausible rows, units a feed drive can
have, a sidecar that does not contradict the CSV) and :func:`load_checked_runs`."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..data import Run, check_plausible, load_runs, sidecar_path
from ..model_file import ModelFile
from ..outputs import Reads, check_file
from ..paper import STROKE
from ..plausibility import check_units
from .sidecar import Sidecar, read_run_sidecar


def model_stroke(model: ModelFile | None) -> tuple[float, float]:
    """The stroke ``stroke.x_min``, ``stroke.x_max`` of a model [m] (the paper's without one)."""
    if model is None:
        return STROKE
    p = model.parameters
    return float(p.get("stroke.x_min", STROKE[0])), float(p.get("stroke.x_max", STROKE[1]))


def check_run(run: Run, model: ModelFile | None = None) -> Sidecar:
    """The refusals every command that reads a measured run applies before any work.

    :func:`feeddrive.data.check_plausible` (rows, magnitudes, sampling, a run that carries
    something), :func:`feeddrive.plausibility.check_units` (positions, speeds,
    accelerations and currents a feed drive can have, against the stroke of ``model``, the
    paper's without one: the likely unit mistake), then the sidecar
    (:func:`~feeddrive.harness.sidecar.read_run_sidecar`): refused only where it
    contradicts the CSV; what it says that the tools do not understand (unknown keys, a
    controller the registry cannot build) is left out of ``run.meta`` and named in the
    returned sidecar's ``note_line()``.  Raises ValueError naming the CSV or the JSON file
    and the field.
    """
    check_plausible(run)
    check_units(run, model_stroke(model))
    return read_run_sidecar(run)


def load_checked_runs(
    runs_dir: str | Path,
    out: str | Path | None = None,
    truth: Any = None,
    notes: list[str] | None = None,
) -> list[Run]:
    """The runs of ``runs_dir``, each checked (:func:`check_run`), after checking that ``out``
    may be written (writable, not an input such as a ``truth`` file); ValueError if none.
    With ``notes`` a list, one line per run whose sidecar says something the tools do not
    use (the keys ignored, the replay that cannot be done) is appended to it."""
    inputs = (truth,) if isinstance(truth, (str, Path)) else ()
    if out is not None:
        check_file(out, Reads.of(files=inputs, run_folders=[runs_dir]))
    runs = load_runs(runs_dir)
    if not runs:
        raise ValueError(f"identify: {runs_dir} holds no run (*.csv or *.csv.gz)")
    for run in runs:
        line = check_run(run).note_line(str(sidecar_path(run.path)) if run.path else run.name)
        if line and notes is not None:
            notes.append(line)
    return runs
