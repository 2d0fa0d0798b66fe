"""Sensitivities of a study's metrics to its parameters, from the results table.

- an ``oat`` study: the change of each metric when one parameter goes to its low and to its
  high end (the others at base): the tornado chart's bars;
- a sampled study (grid, lhs, monte_carlo): Spearman's rank correlation of each parameter
  with each metric over the runs that succeeded (scipy.stats.spearmanr).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.stats import spearmanr

from .run import OK
from .spec import Study


@dataclass(frozen=True)
class Sensitivity:
    """One parameter's effect on one metric.

    ``oat``: ``low`` / ``high`` are the metric's change from base at the parameter's ends
    and ``value`` = high - low; sampled: ``value`` is Spearman's rho (low, high NaN).
    """

    parameter: str
    metric: str
    kind: str  #: "oat" or "spearman"
    low: float
    high: float
    value: float


def _oat(study: Study, rows: Sequence[dict[str, Any]]) -> list[Sensitivity]:
    by_label = {r["label"]: r for r in rows if r["status"] == OK}
    base = by_label.get("base")
    out = []
    for m in study.metric_columns:
        for p in study.parameter_names:
            lo, hi = by_label.get(f"{p}=low"), by_label.get(f"{p}=high")
            if base is None or lo is None or hi is None:
                d_lo = d_hi = math.nan
            else:
                d_lo, d_hi = lo[m] - base[m], hi[m] - base[m]
            out.append(Sensitivity(p, m, "oat", d_lo, d_hi, d_hi - d_lo))
    return out


def _spearman(study: Study, rows: Sequence[dict[str, Any]]) -> list[Sensitivity]:
    out = []
    for m in study.metric_columns:
        ok = [r for r in rows if r["status"] == OK and math.isfinite(r[m])]
        y = np.array([r[m] for r in ok], dtype=float)
        for p in study.parameter_names:
            x = np.array([r[p] for r in ok], dtype=float)
            rho = math.nan
            if len(ok) >= 3 and np.ptp(x) > 0 and np.ptp(y) > 0:
                rho = float(spearmanr(x, y).statistic)
            out.append(Sensitivity(p, m, "spearman", math.nan, math.nan, rho))
    return out


def sensitivities(study: Study, rows: Sequence[dict[str, Any]]) -> list[Sensitivity]:
    """Every (metric, parameter) sensitivity, largest |value| first within each metric."""
    s = _oat(study, rows) if study.design["type"] == "oat" else _spearman(study, rows)
    order = {m: j for j, m in enumerate(study.metric_columns)}
    return sorted(
        s, key=lambda e: (order[e.metric], -abs(e.value) if math.isfinite(e.value) else math.inf)
    )


def sensitivity_text(items: Sequence[Sensitivity]) -> str:
    """The sensitivity table as aligned text (metrics in their SI units)."""
    if not items:
        return ""
    if items[0].kind == "oat":
        head = f"{'metric':<18} {'parameter':<22} {'change at low':>14} {'change at high':>15}"
        lines = [f"{s.metric:<18} {s.parameter:<22} {s.low:>14.4g} {s.high:>15.4g}" for s in items]
    else:
        head = f"{'metric':<18} {'parameter':<22} {'Spearman rho':>13}"
        lines = [f"{s.metric:<18} {s.parameter:<22} {s.value:>13.3f}" for s in items]
    return "\n".join([head] + lines)
