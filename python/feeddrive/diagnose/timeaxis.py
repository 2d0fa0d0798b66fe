"""The time axis of the localisation: the residual per time block of each run and its trend.

A residual that grows or shrinks over a run (a motor warming up, a gain drifting, wear) has
no regime or position of its own; cut in time it shows.  Each run is cut into
``N_TIME_BLOCKS`` blocks of equal duration over its valid samples; per block the rms
residual, the rms noise floor and the excess over it ``sqrt(max(rms^2 - floor^2, 0))``.
The trend is the least-squares slope of the blocks' rms residual against the blocks' mid
times [N/s], and the change from the first to the last block relative to the run's rms.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise

import numpy as np

from ..residual import RunResidual

#: Time blocks per run.
N_TIME_BLOCKS = 8


def time_blocks(
    q: RunResidual, n_blocks: int = N_TIME_BLOCKS
) -> list[tuple[float, float, np.ndarray]]:
    """(t_lo, t_hi, mask over the run's samples) of equal-duration blocks of the valid part."""
    t = np.asarray(q.time, dtype=float)
    tv = t[q.valid]
    if tv.size == 0:
        return []
    edges = np.linspace(float(tv[0]), float(tv[-1]), n_blocks + 1)
    out = []
    for k, (lo, hi) in enumerate(pairwise(edges)):
        m = q.valid & (t >= lo) & ((t < hi) if k < n_blocks - 1 else (t <= hi))
        out.append((float(lo), float(hi), m))
    return out


def run_time_axis(
    q: RunResidual, sigma: np.ndarray | None = None, n_blocks: int = N_TIME_BLOCKS
) -> dict:
    """The time axis of one run (see the module docstring); ``sigma`` the per-sample noise
    floor [N] (no floor columns without it)."""
    rows = []
    for lo, hi, m in time_blocks(q, n_blocks):
        if not m.any():
            continue
        rms = float(np.sqrt(np.mean(q.r[m] ** 2)))
        row = {"t_lo_s": lo, "t_hi_s": hi, "rms_N": rms, "mean_N": float(np.mean(q.r[m]))}
        if sigma is not None:
            fl = float(np.sqrt(np.mean(sigma[m] ** 2)))
            row.update({"floor_N": fl, "excess_N": float(np.sqrt(max(rms**2 - fl**2, 0.0)))})
        rows.append(row)
    out: dict = {"blocks": rows}
    if len(rows) >= 2:
        tm = np.array([(b["t_lo_s"] + b["t_hi_s"]) / 2 for b in rows])
        rms_b = np.array([b["rms_N"] for b in rows])
        slope = float(np.polyfit(tm, rms_b, 1)[0])
        run_rms = float(np.sqrt(np.mean(q.r[q.valid] ** 2)))
        out["trend_N_per_s"] = slope
        out["change_first_to_last"] = float((rms_b[-1] - rms_b[0]) / max(run_rms, 1e-300))
    return out


def time_axis(
    res: Sequence[RunResidual],
    sigma: Sequence[np.ndarray] | None = None,
    n_blocks: int = N_TIME_BLOCKS,
) -> dict:
    """Per run :func:`run_time_axis`, and the run whose residual changes most over its time
    (largest ``|change_first_to_last|``)."""
    runs = {
        q.name: run_time_axis(q, None if sigma is None else sigma[j], n_blocks)
        for j, q in enumerate(res)
    }
    ranked = [k for k in runs if "change_first_to_last" in runs[k]]
    top = max(ranked, key=lambda k: abs(runs[k]["change_first_to_last"])) if ranked else None
    return {
        "runs": runs,
        "largest_change_run": top,
        "largest_change": runs[top]["change_first_to_last"] if top else None,
    }


def trend_text(ax: dict) -> str | None:
    """A phrase for the verdict when a run's residual changes over its time by more than a
    third of its rms, else None."""
    top = ax.get("largest_change_run")
    if top is None or abs(ax["largest_change"]) < 1 / 3:
        return None
    rows = ax["runs"][top]["blocks"]
    word = "grows" if ax["largest_change"] > 0 else "shrinks"
    return (
        f"over run time the residual {word} ({top}: {rows[0]['rms_N']:.3g} N rms in the "
        f"first time block, {rows[-1]['rms_N']:.3g} N in the last)"
    )
