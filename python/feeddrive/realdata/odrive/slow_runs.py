"""Slow runs: the steady part, velocity ripple, and Iq against the map at the run's position
(as measured and behind a first-order lag)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import optimize, signal

from .recordings import COUNTS_PER_REV, CoggingMap, SlowRun
from .spectrum import family, revolution_spectrum, synthesise

SETTLE_S = 0.5  # slow runs: time dropped after the start transient's minimum
RESAMPLE_S = 1e-3  # uniform grid for the Iq-lag filter (samples are ~2.3 ms apart)


@dataclass(frozen=True)
class SlowRunFindings:
    """One slow run (steady part): speed, velocity ripple and Iq against the static map."""

    name: str
    speed: float  # mean velocity [rev/s]
    velocity_std: float  # std of velocity [counts/s]
    r_static: float  # corr(Iq, map at the run's position)
    lag_s: float  # first-order lag of Iq behind map(position(t)) that fits best
    r_lagged: float  # corr(Iq, lagged map)
    r_lagged_no_crosstalk: float  # same with the crosstalk family removed from the map


def steady_part(run: SlowRun) -> np.ndarray:
    """Mask of the steady ramp: drop the start (some runs first swing back from the previous
    run's end, through a minimum) up to SETTLE_S after the minimum of the first quarter."""
    return run.time >= run.time[np.argmin(run.position[: run.time.size // 4])] + SETTLE_S


def velocity(time: np.ndarray, position: np.ndarray) -> np.ndarray:
    """Velocity [counts/s]: second-order differences on the non-uniform time stamps."""
    return np.gradient(position, time)


def _lag_correlation(
    t: np.ndarray, pos: np.ndarray, cur: np.ndarray, m: CoggingMap, values: np.ndarray, tau: float
) -> float:
    tu = np.arange(t[0], t[-1], RESAMPLE_S)
    mu = np.interp(np.interp(tu, t, pos) % COUNTS_PER_REV, m.counts, values, period=COUNTS_PER_REV)
    num, den, _ = signal.cont2discrete(
        (np.array([1.0]), np.array([tau, 1.0])), RESAMPLE_S, method="zoh"
    )
    num = np.ravel(num)
    y, _ = signal.lfilter(num, den, mu, zi=signal.lfilter_zi(num, den) * mu[0])
    return float(np.corrcoef(cur, np.interp(t, tu, y))[0, 1])


def slow_run(run: SlowRun, m: CoggingMap, crosstalk_order: int) -> SlowRunFindings:
    """Analyse one run against map ``m`` (forward map, same encoder frame)."""
    keep = steady_part(run)
    t, pos, cur = run.time[keep], run.position[keep], run.current[keep]
    v = velocity(t, pos)
    static = np.interp(pos % COUNTS_PER_REV, m.counts, m.current, period=COUNTS_PER_REV)
    fit = optimize.minimize_scalar(
        lambda tau: -_lag_correlation(t, pos, cur, m, m.current, tau),
        bounds=(1e-3, 0.5),
        method="bounded",
        options={"xatol": 1e-3},
    )
    spec = revolution_spectrum(m)
    spec[family(crosstalk_order, spec.size)] = 0.0
    clean = synthesise(spec, np.arange(1, spec.size), m.counts)
    return SlowRunFindings(
        run.name,
        float((pos[-1] - pos[0]) / (t[-1] - t[0]) / COUNTS_PER_REV),
        float(v.std()),
        float(np.corrcoef(cur, static)[0, 1]),
        float(fit.x),
        float(-fit.fun),
        _lag_correlation(t, pos, cur, m, clean, float(fit.x)),
    )
