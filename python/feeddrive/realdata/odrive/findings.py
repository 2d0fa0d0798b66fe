"""The whole analysis of the data folder and its findings."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .along_revolution import Stationarity, stationarity
from .forward_reverse import FrictionFindings, friction
from .recordings import (
    ISOLATED_MAP,
    MAP_FOLDER,
    REFERENCE_MAP,
    REPEAT_TRIALS,
    REVERSE_16,
    SLOW_FOLDERS,
    load_maps,
    load_slow_run,
)
from .slow_runs import SlowRunFindings, slow_run
from .spectrum import Line, line_of, line_orders, revolution_spectrum, top_lines
from .trials import TrialComparison, best_shift, compare_trial

N_TRACKED = 6  # lines tracked along the revolution (adds 84/rev = lcm(12, 14))


@dataclass(frozen=True)
class OdriveFindings:
    """Everything :func:`analyse` finds (counts, A, s)."""

    reference: str
    lines: tuple[Line, ...]  # top lines of the reference forward map
    grid_check: float  # max rel. change of those amplitudes over steps 4..32
    isolated_lines: tuple[Line, ...]  # the same orders in iso_16
    isolated_shift: tuple[int, float]  # iso_16 registration vs reference [counts], correlation
    crosstalk_order: int  # the line that drops most without the neighbour
    stationarity: tuple[Stationarity, ...]
    trials: tuple[TrialComparison, ...]
    friction: FrictionFindings
    slow: tuple[SlowRunFindings, ...]


def analyse(folder: str | Path) -> OdriveFindings:
    """Run the whole analysis on the data folder (``.../realdata/odrive-cogging``)."""
    folder = Path(folder)
    maps = load_maps(folder)
    for need in (REFERENCE_MAP, ISOLATED_MAP, *REPEAT_TRIALS, *REVERSE_16):
        if need not in maps:
            raise FileNotFoundError(f"{folder / MAP_FOLDER}: map {need} missing")
    ref = maps[REFERENCE_MAP]
    spec = revolution_spectrum(ref)
    lines = top_lines(spec)
    orders = tuple(ln.order for ln in lines)
    others = [
        revolution_spectrum(mm)
        for k, mm in maps.items()
        if k.startswith("a_") and k != REFERENCE_MAP
    ]
    grid = max(abs(abs(s[q]) / abs(spec[q]) - 1.0) for s in others for q in orders)
    iso_spec = revolution_spectrum(maps[ISOLATED_MAP])
    iso = tuple(line_of(iso_spec, q) for q in orders)
    xt = min(orders, key=lambda q: abs(iso_spec[q]) / abs(spec[q]))
    tracked = tuple(ln.order for ln in top_lines(spec, N_TRACKED))
    stat = tuple(
        stationarity(maps[k], line_orders(spec), tracked)
        for k in (REFERENCE_MAP, *REPEAT_TRIALS, ISOLATED_MAP, *REVERSE_16)
    )
    trials = tuple(compare_trial(ref, maps[k], xt) for k in REPEAT_TRIALS)
    runs = []
    for sub in SLOW_FOLDERS:
        d = folder / sub
        if not d.is_dir():
            raise FileNotFoundError(f"{d}: slow-run folder not found")
        runs += [slow_run(load_slow_run(p), ref, xt) for p in sorted(d.glob("*.npy"))]
    return OdriveFindings(
        ref.name,
        lines,
        float(grid),
        iso,
        best_shift(ref, maps[ISOLATED_MAP]),
        int(xt),
        stat,
        trials,
        friction(maps, xt),
        tuple(runs),
    )


def slow_summary(f: OdriveFindings) -> dict[str, dict[str, float]]:
    """Slow-run numbers averaged over trials, keyed ``"<folder>/<kind>"`` (kind: nocomp, comp,
    crosstalk_nocomp, crosstalk_comp)."""
    groups: dict[str, list[SlowRunFindings]] = {}
    for s in f.slow:
        groups.setdefault(s.name.rsplit("_", 1)[0], []).append(s)
    fields = ("speed", "velocity_std", "r_static", "lag_s", "r_lagged", "r_lagged_no_crosstalk")
    return {
        k: {a: float(np.mean([getattr(s, a) for s in v])) for a in fields} | {"n": len(v)}
        for k, v in groups.items()
    }
