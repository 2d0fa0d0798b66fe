"""Coverage of the identification's intervals over independent campaigns made by the FMU.

K campaigns are simulated on a non-paper truth (:func:`coverage_truth`), each with its own
sensor noise; each is identified and given intervals by a method of ``identify --bootstrap``
('parametric': bias-corrected from simulated campaigns; 'runs': percentiles over resampled
whole runs).  Per parameter: how often the truth lies inside the interval, how often an
interval was refused, the mean width; a binomial test says whether the count is as high as
a binomial(K, level) allows (:func:`lowest_count`: below its 1 % quantile is a failure).

The campaign (:func:`coverage_campaign`) is the part of the identification campaign that
identifies the current loop, the Stribeck curve and the mass: one PRBS run, six speeds of
constant-speed runs in both directions (:data:`SPEEDS`), the open-loop force run; the
position maps keep the paper's values (the truth has them too).  ``repeats`` repeats every
run with fresh noise (the 'runs' method needs two or more).

``python -m feeddrive.study.coverage --campaigns 20 --replicates 20 --out FILE.json``
(``make interval-coverage``) runs the study and writes the table and every campaign's
intervals.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

from ..data import Run
from ..effects import experiment_running
from ..experiments.constant_speed import stribeck_runs
from ..experiments.force_open_loop import force_open_loop_runs
from ..experiments.prbs import prbs_runs
from ..experiments.recording import run_seed
from ..harness.sensors import Sensors
from ..identify.pipeline import identify_runs
from ..model_file import ModelFile, paper_model
from .bootstrap import METHODS, run_bootstrap, run_parametric

#: Constant-speed runs of the campaign [m/s] (both directions each).
SPEEDS = (0.5e-3, 1e-3, 2e-3, 8e-3, 30e-3, 120e-3)
#: The parameters the campaign identifies and the study checks.
CHECKED = (
    "m",
    "friction.F_s",
    "friction.F_c",
    "friction.V_s",
    "friction.delta",
    "friction.sigma2",
    "current.a[1]",
    "current.a[2]",
    "current.b[2]",
    "current.b[3]",
)


def coverage_truth() -> ModelFile:
    """The paper's model with the mass, the current loop's gain and the Stribeck curve
    changed (physically plausible, not the paper's)."""
    p = dict(paper_model().parameters)
    p["m"] *= 1.07
    p["current.b[2]"] *= 1.05
    p["current.b[3]"] *= 1.05
    p["friction.F_s"] *= 1.10
    p["friction.F_c"] *= 1.08
    p["friction.V_s"] *= 1.3
    p["friction.delta"] = 0.7
    p["friction.sigma2"] *= 0.9
    return ModelFile(
        name="coverage truth",
        effects=paper_model().effects,
        parameters=p,
        description="paper model, mass, current-loop gain and Stribeck changed",
    )


def _jobs():
    yield "prbs", partial(prbs_runs, periods=1)
    yield (
        experiment_running(stribeck_runs).group,
        partial(stribeck_runs, speeds=SPEEDS, cruise_time=1.0, min_length=3e-3),
    )
    yield "force", partial(force_open_loop_runs, n_periods=5)


def coverage_campaign(k: int, repeats: int = 1, truth: ModelFile | None = None) -> list[Run]:
    """Campaign ``k``: every run of the module docstring ``repeats`` times, noise seeds from
    (k, run, repeat) at the default sensor noise."""
    params = (truth or coverage_truth()).fmu_parameters()
    out: list[Run] = []
    for rep in range(repeats):
        for label, fn in _jobs():
            runs = fn(params, Sensors(seed=run_seed(1_000_003 + k, label, rep)))
            for r in runs:
                r.meta["name"] = f"{r.meta['name']}_r{rep + 1}"
            out += runs
    return out


def lowest_count(K: int, level: float = 0.95, alpha: float = 0.01) -> int:
    """The smallest number of covering intervals out of K that a binomial(K, level) gives
    with probability >= alpha in its lower tail: fewer is a failure of the intervals."""
    return int(stats.binom.ppf(alpha, K, level))


@dataclass
class Coverage:
    """Per parameter: intervals given, truth inside, refusals, widths; per campaign rows."""

    method: str
    level: float
    replicates: int
    repeats: int
    names: tuple[str, ...]
    rows: list[dict[str, Any]] = field(default_factory=list)
    cpu_s: float = 0.0

    def summary(self) -> dict[str, dict[str, Any]]:
        """``{name: {given, inside, refused, mean_rel_width, mean_abs_bias_rel}}``."""
        out: dict[str, dict[str, Any]] = {}
        truth = coverage_truth().parameters
        for n in self.names:
            given = [r[n] for r in self.rows if r[n].get("lo") is not None]
            inside = sum(g["lo"] <= truth[n] <= g["hi"] for g in given)
            widths = [(g["hi"] - g["lo"]) / abs(truth[n]) for g in given]
            out[n] = {
                "given": len(given),
                "inside": inside,
                "refused": len(self.rows) - len(given),
                "mean_rel_width": float(np.mean(widths)) if widths else math.nan,
                "mean_rel_error": float(
                    np.mean([abs(r[n]["estimate"] - truth[n]) / abs(truth[n]) for r in self.rows])
                ),
            }
        return out

    def failures(self, alpha: float = 0.01) -> list[str]:
        """Parameters whose count of covering intervals is below the binomial quantile."""
        bad = []
        for n, s in self.summary().items():
            if s["given"] and s["inside"] < lowest_count(s["given"], self.level, alpha):
                bad.append(
                    f"{n}: truth inside {s['inside']} of {s['given']} intervals "
                    f"(binomial({s['given']}, {self.level}) 1 % quantile "
                    f"{lowest_count(s['given'], self.level, alpha)})"
                )
        return bad

    def table(self) -> str:
        """A Markdown table: parameter, intervals given, truth inside, mean width."""
        L = [
            f"method {self.method}, {len(self.rows)} campaigns, {self.replicates} replicates, "
            f"{self.repeats} repeat(s) of every run, level {self.level}, "
            f"{self.cpu_s:.0f} s",
            "| parameter | intervals | truth inside | refused | mean width (% of value) "
            "| mean estimate error (%) |",
            "|---|---|---|---|---|---|",
        ]
        for n, s in self.summary().items():
            L.append(
                f"| {n} | {s['given']} | {s['inside']} | {s['refused']} | "
                f"{100 * s['mean_rel_width']:.3g} | {100 * s['mean_rel_error']:.3g} |"
            )
        return "\n".join(L)


def campaign_intervals(
    runs: Sequence[Run],
    method: str,
    replicates: int,
    seed: int,
    level: float,
    names: Sequence[str],
    parallel: bool = False,
    workers: int | None = None,
) -> dict[str, dict[str, Any]]:
    """One campaign's row: per parameter the estimate and the interval (lo, hi; None when
    refused, with the reason)."""
    fit = identify_runs(runs)
    if method == "runs":
        boot = run_bootstrap(
            runs,
            fit.model,
            fit.defaulted,
            replicates,
            seed=seed,
            level=level,
            parallel=parallel,
            workers=workers,
        )
    else:
        boot = run_parametric(
            runs, fit, replicates, seed=seed, level=level, parallel=parallel, workers=workers
        )
    row: dict[str, dict[str, Any]] = {}
    for n in names:
        iv = boot.uncertainty.get(n)
        row[n] = {
            "estimate": float(fit.model.parameters[n]),
            "lo": iv["lo"] if iv else None,
            "hi": iv["hi"] if iv else None,
            "bias": iv.get("bias") if iv else None,
            "refused": boot.refused.get(n, "" if iv else "no interval"),
        }
    return row


def coverage_study(
    K: int,
    method: str = "parametric",
    replicates: int = 20,
    repeats: int = 1,
    level: float = 0.95,
    names: Sequence[str] = CHECKED,
    parallel: bool = False,
    workers: int | None = None,
    log: Any = None,
    first: int = 0,
) -> Coverage:
    """K campaigns (:func:`coverage_campaign` first..first+K-1), each identified and given
    intervals by ``method``; the truth is :func:`coverage_truth`."""
    if method not in METHODS:
        raise ValueError(f"method {method!r}: must be one of {', '.join(METHODS)}")
    cov = Coverage(
        method=method, level=level, replicates=replicates, repeats=repeats, names=tuple(names)
    )
    t0 = time.process_time()
    for k in range(first, first + K):
        runs = coverage_campaign(k, repeats)
        cov.rows.append(
            campaign_intervals(
                runs,
                method,
                replicates,
                seed=k,
                level=level,
                names=names,
                parallel=parallel,
                workers=workers,
            )
        )
        if log is not None:
            print(
                f"campaign {k + 1 - first}/{K} done ({time.process_time() - t0:.0f} s cpu)",
                file=log,
                flush=True,
            )
    cov.cpu_s = time.process_time() - t0
    return cov


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m feeddrive.study.coverage``: the study, its table, a JSON of every row."""
    ap = argparse.ArgumentParser(
        prog="python -m feeddrive.study.coverage",
        description="coverage of identify --bootstrap intervals",
    )
    ap.add_argument("--campaigns", type=int, default=20)
    ap.add_argument("--first", type=int, default=0, help="number of the first campaign")
    ap.add_argument("--replicates", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--method", choices=METHODS, default="parametric")
    ap.add_argument("--level", type=float, default=0.95)
    ap.add_argument("--out", type=Path, default=None, help="JSON file of the rows and table")
    a = ap.parse_args(argv)
    cov = coverage_study(
        a.campaigns, a.method, a.replicates, a.repeats, a.level, log=sys.stderr, first=a.first
    )
    print(cov.table())
    for f in cov.failures():
        print("BELOW THE BINOMIAL QUANTILE:", f)
    if a.out is not None:
        a.out.write_text(
            json.dumps({"table": cov.table(), "summary": cov.summary(), "rows": cov.rows}, indent=1)
            + "\n",
            encoding="utf-8",
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
