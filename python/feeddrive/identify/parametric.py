"""Parametric bootstrap of the identification: its bias and spread by simulation, and
intervals that include the bias.

The identified model ``theta_hat`` is taken as the plant; every recorded run of the campaign
is made again on it (:func:`feeddrive.experiments.resimulate.resimulate`: the same
experiment, the same controller and reference, fresh sensor noise at the campaign's
**measured** noise level, :func:`measured_sensors`), and the whole pipeline identifies the
simulated campaign again.  Over B such replicates ``theta*_b``:

- bias ``b = mean(theta*) - theta_hat`` (what the method adds on its own: the Stribeck
  fit's systematic offset, the shift the noise acting on the stage as a force gives the
  friction, ...);
- spread ``s = std(theta*)`` (ddof 1): the noise-driven scatter of the estimate, the current
  loop's from the one PRBS run it is fitted to (every replicate has its own noise in that
  run: a within-run spread, not R whole runs; a PRBS run the sidecar does not describe has
  its current made again from its recorded u, :func:`current_only`);
- the interval ``theta_hat - b +- t_{B-1,(1+level)/2} s sqrt(1 + 1/B)``: centred on the
  bias-corrected estimate; ``sqrt(1 + 1/B)`` carries the error of the bias estimated from B
  replicates and Student's t the error of ``s`` (a prediction interval for a normal
  estimator: its level holds for B as small as 10, where percentile or BCa end points from
  B = 10..50 replicates would scatter by a large fraction of their width).

The bias at ``theta_hat`` stands for the bias at the truth: right to first order when the
bias changes slowly with the parameters.  The noise model is white current noise (the rms
the PRBS fit leaves) acting on the stage, the scale quantised at the recorded resolution;
what the model leaves out (coloured noise, drifts, effects the model does not have) is not
in the intervals: that is the diagnosis' business.

Refusals (a parameter gets no interval, and the reason is kept):

- fewer than :data:`MIN_REPLICATES` successful replicates, or more than
  :data:`MAX_FAILED_SHARE` of them failed (the estimate's distribution is cut);
- the current loop's coefficients when fewer than :data:`STRUCTURE_SHARE` of the replicates
  choose the estimate's order and delay (the PRBS run does not determine the structure;
  coefficients of different structures are not one quantity); otherwise the coefficients'
  intervals come from the replicates of that structure (conditional on it);
- no spread (the same value in every replicate, :attr:`Intervals.fixed`: the sample time,
  coefficients the structure fixes at zero) is no interval, and not a refusal.

Replicate ``r`` simulates run ``j`` with noise seed ``run_seed(seed, r, j)`` and depends
on (seed, r) only: serial, on workers or on a cluster, the same rows.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import stats

from ..data import Run
from ..experiments.recording import run_seed
from ..experiments.resimulate import can_resimulate, resimulate
from ..harness.sensors import Sensors
from ..harness.sidecar import read_sidecar
from ..signals import run_label
from .classification import classify
from .pipeline import identify_runs
from .result import IdentificationResult

OK, FAILED = "ok", "failed"
MIN_REPLICATES = 10  #: fewest successful replicates for an interval
MAX_FAILED_SHARE = 0.1  #: most replicates that may fail before every interval is refused
STRUCTURE_SHARE = 0.8  #: least share of replicates choosing the estimate's G(z) structure
METHOD = "parametric"


def measured_sensors(runs: Sequence[Run], fit: IdentificationResult) -> tuple[Sensors, str]:
    """The campaign's noise as measured: the current noise rms the current-loop fit leaves
    on its PRBS run (else the sidecars' ``current_noise``), the scale resolution as the
    smallest position step the runs record (else the sidecars' ``quantum``), and whether
    the noise acts on the stage (sidecar, default yes).  Returns the sensors and a sentence
    saying where each number came from; ValueError when the current noise is nowhere."""
    sides = [read_sidecar(r.meta, where=f"{run_label(r)}: sidecar") for r in runs]
    said = [r.meta.get("sensors") if r.meta else None for r in runs]
    if fit.current_loop is not None:
        noise, n_src = float(fit.current_loop.rms_residual), "the current-loop fit's residual rms"
    elif all(s is not None for s in said):
        noise = float(np.median([s.sensors.current_noise for s in sides]))
        n_src = "the sidecars' current_noise"
    else:
        raise ValueError(
            "identify --bootstrap: the current noise is not known (no PRBS run to "
            "measure it, no sidecar 'sensors.current_noise')"
        )
    steps = np.concatenate([np.abs(np.diff(np.asarray(r.x, float))) for r in runs])
    steps = steps[steps > 0]
    if steps.size:
        q = float(np.min(steps))
        quantum, q_src = float(f"{q:.3g}"), "the smallest recorded position step"
    else:
        quantum, q_src = float(np.median([s.sensors.quantum for s in sides])), "the sidecars"
    on_stage = all(s.sensors.noise_on_stage for s in sides)
    text = (
        f"current noise {noise * 1e3:.3g} mA rms ({n_src}), scale {quantum * 1e9:.3g} nm "
        f"({q_src}), noise {'acting on the stage' if on_stage else 'in the measurement only'}"
    )
    return Sensors(quantum=quantum, current_noise=noise, noise_on_stage=on_stage), text


def current_only(runs: Sequence[Run]) -> tuple[bool, ...]:
    """Per run: True for a PRBS run that cannot be simulated whole (its current is made again
    from its recorded u: all the current loop's fit reads)."""
    return tuple(classify(r) == "prbs" and can_resimulate(r) is not None for r in runs)


def why_not_resimulable(runs: Sequence[Run]) -> str | None:
    """None when every run can be simulated again (whole, or its current for a PRBS run),
    else the first run's reason."""
    for r, cur in zip(runs, current_only(runs), strict=True):
        why = None if cur else can_resimulate(r)
        if why is not None:
            return f"a parametric bootstrap simulates every run again; {why}"
    return None


@dataclass(frozen=True)
class ParametricTask:
    """What a worker needs for any replicate (picklable): the recorded campaign, the
    identified model's FMU parameters, the measured noise, the names, the seed, options."""

    runs: tuple[Run, ...]
    params: tuple[tuple[str, Any], ...]
    sensors: Sensors
    names: tuple[str, ...]
    seed: int
    options: tuple[tuple[str, Any], ...] = ()
    current_only: tuple[bool, ...] = ()  #: per run: only its current made again


def simulated_campaign(task: ParametricTask, replicate: int) -> list[Run]:
    """Replicate ``replicate``'s campaign: every run made again on the identified model."""
    params = dict(task.params)
    out = []
    for j, run in enumerate(task.runs):
        s = Sensors(
            quantum=task.sensors.quantum,
            current_noise=task.sensors.current_noise,
            noise_on_stage=task.sensors.noise_on_stage,
            seed=run_seed(task.seed, int(replicate), j),
        )
        new = resimulate(
            run, params, s, current_only=bool(task.current_only and task.current_only[j])
        )
        new.meta["name"] = run.name
        out.append(new)
    return out


def run_replicate(task: ParametricTask, replicate: int) -> dict[str, Any]:
    """One replicate's row: replicate, the re-identified parameters, the current loop's
    ``structure`` (order/delay, '' without one), wall_s, status, message."""
    t0 = time.perf_counter()
    row: dict[str, Any] = {"replicate": int(replicate)}
    values = dict.fromkeys(task.names, math.nan)
    structure = ""
    try:
        res = identify_runs(simulated_campaign(task, replicate), **dict(task.options))
        values.update({n: float(res.model.parameters[n]) for n in task.names})
        if res.current_loop is not None:
            structure = f"{res.current_loop.order}/{res.current_loop.delay}"
        status, message = OK, ""
    except Exception as e:  # a replicate a step refuses is a row, not a crash
        status, message = FAILED, f"{type(e).__name__}: {e}".replace("\n", " ")
    row.update(values)
    row.update(
        {
            "structure": structure,
            "wall_s": time.perf_counter() - t0,
            "status": status,
            "message": message,
        }
    )
    return row


def run_replicates(task: ParametricTask, batch: Sequence[int]) -> list[dict[str, Any]]:
    """:func:`run_replicate` of every replicate of a batch (one executor task)."""
    return [run_replicate(task, r) for r in batch]


@dataclass
class Intervals:
    """Intervals (model-file form, with ``method`` and ``bias``), the evidence behind each
    (bias, spread, replicates) and the parameters refused with the reason."""

    uncertainty: dict[str, dict[str, Any]]
    evidence: dict[str, dict[str, float]] = field(default_factory=dict)
    refused: dict[str, str] = field(default_factory=dict)
    #: identified but the same in every replicate (the sample time, coefficients the
    #: structure fixes at zero): no spread to give an interval
    fixed: list[str] = field(default_factory=list)


def bias_corrected(
    estimate: Mapping[str, float],
    rows: Sequence[dict[str, Any]],
    names: Sequence[str],
    level: float,
    structure: str = "",
) -> Intervals:
    """The intervals of the module docstring from the replicates' rows."""
    ok = [r for r in rows if r["status"] == OK]
    out = Intervals(uncertainty={})
    failed = len(rows) - len(ok)
    if len(ok) < MIN_REPLICATES or failed > MAX_FAILED_SHARE * len(rows):
        why = (
            f"{len(ok)} of {len(rows)} simulated campaigns identified (an interval needs "
            f">= {MIN_REPLICATES} and at most {MAX_FAILED_SHARE:.0%} failed)"
        )
        out.refused = dict.fromkeys(names, why)
        return out
    same = [r for r in ok if r["structure"] == structure]
    share = len(same) / len(ok)
    for n in names:
        use = ok
        if n.startswith("current."):
            if share < STRUCTURE_SHARE:
                others = sorted({r["structure"] for r in ok} - {structure})
                out.refused[n] = (
                    f"the current loop's order/delay {structure} came back in "
                    f"{len(same)} of {len(ok)} simulated campaigns (others: "
                    f"{', '.join(others)}): the PRBS run does not determine the "
                    f"structure (an interval needs {STRUCTURE_SHARE:.0%})"
                )
                continue
            use = same
        v = np.array([r[n] for r in use], dtype=float)
        if not np.all(np.isfinite(v)):
            out.refused[n] = "not finite in some simulated campaigns"
            continue
        if np.ptp(v) == 0.0:
            out.fixed.append(n)
            continue
        s = float(np.std(v, ddof=1))
        B = len(use)
        t = float(stats.t.ppf((1 + level) / 2, B - 1))
        bias = float(np.mean(v) - estimate[n])
        centre = float(estimate[n]) - bias
        half = t * s * math.sqrt(1 + 1 / B)
        out.uncertainty[n] = {
            "lo": centre - half,
            "hi": centre + half,
            "level": float(level),
            "replicates": B,
            "method": METHOD,
            "bias": bias,
        }
        out.evidence[n] = {"bias": bias, "spread": s, "replicates": B}
    return out
