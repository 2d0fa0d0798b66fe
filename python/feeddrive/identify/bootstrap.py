"""Identification bootstrap: :func:`~feeddrive.identify.pipeline.identify_runs` repeated over
resampled campaigns, percentile intervals for every identified parameter.

Resampling unit: **whole runs, with replacement, within each cell** of a campaign.  A cell
holds the repeats of one experimental condition (:func:`cells`): the experiment kind and,
for constant-speed runs, the direction, the cruise speed (within ``SPEED_TOL``) and the
load (within ``LOAD_TOL``); for the reversing (pre-rolling) runs the amplitude (within 20 %).  Every
replicate is then a complete campaign of untouched runs with every condition present, so
each step's assumptions hold as for the original: the maps still get a forward/backward
pair at every load, the Stribeck fit every speed in both directions, and no fit sees a
spliced run.  Contiguous blocks within runs are *not* resampled: every step consumes whole
continuous runs (the steady segment of a constant-speed run, Savitzky-Golay derivatives for
the mass, the output-error simulation of the current loop, the GMS memory and half cycles
of the pre-rolling and attraction fits), and a join of two blocks is a jump in x, v or the
filter states those fits would read as physics.  A cell with a single run contributes no
spread: its steps' intervals then only reflect the other cells (:attr:`Bootstrap.single`
lists them); a campaign with no repeated condition is refused.

Every replicate ``r`` draws its resample from ``numpy.random.default_rng([seed, r])`` and
runs the whole pipeline, so a replicate's result depends on (seed, r) only: the same
bootstrap serially, on 2 workers or on a cluster gives the same intervals bit for bit.
A replicate that fails (a step refuses its resample) is a row with its message.
Intervals are the ``(1 - level)/2`` and ``(1 + level)/2`` percentiles (numpy, linear
interpolation) over the replicates that succeeded.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..data import Run
from ..model_file import INTEGER_PARAMETERS, ModelFile
from ..physics import run_load_mean
from ..signals import run_label, sample_time
from ._signals import steady_segment
from .classification import KIND_OF_SHAPE, LOAD_TOL, SPEED_TOL, classify
from .pipeline import identify_runs

OK, FAILED = "ok", "failed"
AMPLITUDE_TOL = 0.2  #: relative amplitude difference within which pre-rolling runs repeat


def _condition(run: Run, kind: str) -> tuple[float, ...]:
    """The numbers that make two runs of ``kind`` repeats of one condition."""
    x = np.asarray(run.x, dtype=float)
    if kind == "constant_speed":
        Ts = sample_time(run.time, label=run_label(run))
        v = steady_segment(x, Ts, label=run_label(run))[1]
        return (float(np.sign(v)), abs(float(v)), float(run_load_mean(run)[0]))
    if KIND_OF_SHAPE.get("reversing") == kind:
        return (float(np.ptp(x)),)
    return ()


def _same(kind: str, a: tuple[float, ...], b: tuple[float, ...]) -> bool:
    if kind == "constant_speed":
        return (
            a[0] == b[0]
            and abs(a[1] - b[1]) <= SPEED_TOL * max(a[1], b[1])
            and abs(a[2] - b[2]) <= LOAD_TOL
        )
    if KIND_OF_SHAPE.get("reversing") == kind:
        return abs(a[0] - b[0]) <= AMPLITUDE_TOL * max(a[0], b[0])
    return True


def cells(runs: Sequence[Run]) -> list[list[int]]:
    """Indices of ``runs`` grouped into cells of repeats (see the module docstring), each
    cell in run order, cells in order of their first run."""
    out: list[tuple[str, tuple[float, ...], list[int]]] = []
    for j, run in enumerate(runs):
        kind = classify(run)
        cond = _condition(run, kind)
        for k, c, members in out:
            if k == kind and _same(kind, c, cond):
                members.append(j)
                break
        else:
            out.append((kind, cond, [j]))
    return [m for _, _, m in out]


def resample(groups: Sequence[Sequence[int]], seed: int, replicate: int) -> list[int]:
    """Run indices of replicate ``replicate``: each cell drawn with replacement, its size kept
    (``numpy.random.default_rng([seed, replicate])``)."""
    rng = np.random.default_rng([seed, replicate])
    out: list[int] = []
    for members in groups:
        out.extend(int(members[k]) for k in rng.integers(0, len(members), len(members)))
    return out


@dataclass(frozen=True)
class BootstrapTask:
    """What a worker needs for any replicate (picklable): the campaign, its cells, the
    parameters to report, the seed and the pipeline's keywords."""

    runs: tuple[Run, ...]
    cells: tuple[tuple[int, ...], ...]
    names: tuple[str, ...]
    seed: int
    options: tuple[tuple[str, Any], ...] = ()


def run_replicate(task: BootstrapTask, replicate: int) -> dict[str, Any]:
    """One replicate's row: replicate, the identified parameters, wall_s, status, message."""
    t0 = time.perf_counter()
    row: dict[str, Any] = {"replicate": int(replicate)}
    values = dict.fromkeys(task.names, math.nan)
    try:
        pick = resample(task.cells, task.seed, replicate)
        res = identify_runs([task.runs[j] for j in pick], **dict(task.options))
        values.update({n: float(res.model.parameters[n]) for n in task.names})
        status, message = OK, ""
    except Exception as e:  # a replicate a step refuses is a row, not a crash
        status, message = FAILED, f"{type(e).__name__}: {e}".replace("\n", " ")
    row.update(values)
    row.update({"wall_s": time.perf_counter() - t0, "status": status, "message": message})
    return row


def run_replicates(task: BootstrapTask, batch: Sequence[int]) -> list[dict[str, Any]]:
    """:func:`run_replicate` of every replicate of a batch (one executor task)."""
    return [run_replicate(task, r) for r in batch]


def identified_names(model: ModelFile, defaulted: Sequence[str]) -> tuple[str, ...]:
    """The real-valued parameters the pipeline identified (not kept at the paper's value)."""
    skip = set(defaulted) | set(INTEGER_PARAMETERS)
    return tuple(n for n in model.parameters if n not in skip)


def intervals(
    rows: Sequence[dict[str, Any]], names: Sequence[str], level: float
) -> dict[str, dict[str, Any]]:
    """Percentile interval of every parameter over the successful replicates:
    ``{name: {"lo", "hi", "level", "replicates"}}`` (empty when none succeeded)."""
    ok = [r for r in rows if r["status"] == OK]
    if not ok:
        return {}
    q = 100 * np.array([(1 - level) / 2, (1 + level) / 2])
    out: dict[str, dict[str, Any]] = {}
    for n in names:
        lo, hi = np.percentile(np.array([r[n] for r in ok], dtype=float), q)
        out[n] = {"lo": float(lo), "hi": float(hi), "level": float(level), "replicates": len(ok)}
    return out


def single_run_parameters(
    rows: Sequence[dict[str, Any]], names: Sequence[str], repeats: int
) -> dict[str, str]:
    """The parameters a single run per replicate feeds (the current loop from one PRBS run,
    the mass from one force run, ...): over the replicates they take at most ``repeats``
    values (the largest cell), so their percentiles are R whole runs' values, not an interval
    of the stated level.  ``{name: why}``; a parameter with one value (fixed) is not one."""
    ok = [r for r in rows if r["status"] == OK]
    out: dict[str, str] = {}
    for n in names:
        k = len({r[n] for r in ok})
        if 1 < k <= repeats:
            out[n] = (
                f"takes only {k} values over {len(ok)} replicates: one run per replicate "
                f"feeds it (cells of {repeats} repeats), no interval from resampling whole "
                "runs (--interval-method parametric resamples within the run)"
            )
    return out


@dataclass
class Bootstrap:
    """A finished bootstrap: rows in replicate order, intervals, cost."""

    rows: list[dict[str, Any]]
    uncertainty: dict[str, dict[str, Any]]
    n_cells: int
    single: list[str] = field(default_factory=list)  #: runs alone in their cell
    wall_s: float = 0.0
    workers: int = 1
    method: str = "runs"  #: 'runs' (this module) or 'parametric' (:mod:`.parametric`)
    refused: dict[str, str] = field(default_factory=dict)  #: parameter -> why no interval
    noise: str = ""  #: the noise the parametric replicates were simulated with
    #: parameter -> bias, spread, replicates behind its parametric interval
    evidence: dict[str, dict[str, float]] = field(default_factory=dict)
    fixed: list[str] = field(default_factory=list)  #: the same in every replicate

    @property
    def failed(self) -> int:
        return sum(r["status"] == FAILED for r in self.rows)

    def text(self) -> str:
        """One line of counts and cost, and the failures' first message."""
        ok = [r for r in self.rows if r["status"] == OK]
        cpu = float(np.mean([r["wall_s"] for r in ok])) if ok else math.nan
        cost = f"in {self.wall_s:.1f} s on {self.workers} worker(s) ({cpu:.2f} s per replicate)"
        if self.method != "runs" and not self.rows:
            return "parametric bootstrap: not run, no intervals: " + "; ".join(
                self.refused.values()
            )
        if self.method != "runs":
            line = (
                f"parametric bootstrap: {len(ok)}/{len(self.rows)} campaigns of "
                f"{self.n_cells} runs simulated on the identified model and identified "
                f"again {cost}; noise: {self.noise}; intervals bias-corrected"
            )
            if self.refused:
                line += (
                    f"\n  no interval for {len(self.refused)} parameters: "
                    + "; ".join(f"{k}: {why}" for k, why in list(self.refused.items())[:3])
                    + (" ..." if len(self.refused) > 3 else "")
                )
            bad = [r for r in self.rows if r["status"] == FAILED]
            if bad:
                line += (
                    f"\n  {len(bad)} failed, e.g. replicate {bad[0]['replicate']}: "
                    f"{bad[0]['message']}"
                )
            return line
        line = (
            f"bootstrap: {len(ok)}/{len(self.rows)} replicates over {self.n_cells} cells "
            f"of repeated runs {cost}; percentile intervals of the noise spread, "
            "without the method's bias"
        )
        if self.refused:
            line += (
                f"\n  no interval for {len(self.refused)} parameters fed by one run per "
                "replicate: "
                + ", ".join(list(self.refused)[:6])
                + (" ..." if len(self.refused) > 6 else "")
            )
        if self.single:
            line += (
                f"; {len(self.single)} runs have no repeat (no spread from them): "
                + ", ".join(self.single[:4])
                + (" ..." if len(self.single) > 4 else "")
            )
        bad = [r for r in self.rows if r["status"] == FAILED]
        if bad:
            line += (
                f"\n  {len(bad)} failed, e.g. replicate {bad[0]['replicate']}: {bad[0]['message']}"
            )
        return line


def check_campaign(runs: Sequence[Run]) -> list[list[int]]:
    """The cells of ``runs``; ValueError when no condition is repeated (no spread)."""
    groups = cells(runs)
    if all(len(g) == 1 for g in groups):
        raise ValueError(
            f"identify --bootstrap: none of the {len(runs)} runs repeats another's "
            "condition (kind, speed, direction, load, amplitude): resampling whole "
            "runs needs repeated runs of at least one experiment"
        )
    return groups
