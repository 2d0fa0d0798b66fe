"""Stribeck curve from constant-speed runs (Sec. 2.4.2, Eqs. 12-13).

Runs come in pairs of opposite direction and equal speed, without load.  For each pair the
currents are resampled onto the 0.1 mm grid of the stroke both runs cover and

    F_f(v) = K_f(x) / 2 (I(x, v, 0) - I(x, -v, 0))        (Eq. 13)

is averaged over position (cogging cancels).  The points (v, F_f) are fitted by Eq. 12 for
v > 0, F = F_c + (F_s - F_c) exp(-(v/V_s)^delta) + sigma2 v, with scipy least_squares (several
starts, best kept), giving standard errors from the Jacobian.

Asymmetry: with F_cg known, K_f (I(v) + I(-v)) - 2 (F_cg + P) = F_+(v) - F_-(v), the
forward minus backward friction magnitude.  The FMU's asymmetry (for v < 0 the levels are
F_c + dF, F_s + dF and the viscous coefficient sigma2 + dsigma2) gives F_+ - F_- =
-(dF + dsigma2 |v|); a line fit returns dF and dsigma2.  A constant offset force and a bias of
F_cg's constant term are indistinguishable from dF here (they enter the same way).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from ..data import Run
from ..physics import MapSpec, eval_map, run_load_mean, steady_friction
from ..signals import run_label, sample_time
from ._signals import (
    common_grid,
    current,
    jacobian_stderr,
    lstsq_with_stderr,
    signal,
    steady_segment,
    to_grid,
)
from .position_maps import GRID_STEP

NAMES = ("friction.F_s", "friction.F_c", "friction.V_s", "friction.delta", "friction.sigma2")


@dataclass
class StribeckPoints:
    """Eq. 13 per speed (one entry per pair of runs)."""

    speed: np.ndarray  #: |v| [m/s] (mean of the pair)
    friction: np.ndarray  #: mean F_f over position [N]
    spread: np.ndarray  #: std of F_f over position [N]
    asymmetry: np.ndarray | None  #: F_+ - F_- [N] (None without F_cg)
    pairs: list[tuple[str, str]]


@dataclass
class StribeckFit:
    """Fit of Eq. 12 (and the asymmetry line when available)."""

    parameters: dict[str, float]  #: friction.F_s, F_c, V_s [m/s], delta, sigma2 [N s/m]
    stderr: dict[str, float]
    points: StribeckPoints
    residual: np.ndarray  #: model - data at the points [N]
    rms_residual: float
    asymmetry: dict[str, float] | None  #: asymmetry.dF, asymmetry.dsigma2 (+ stderr keys)

    def curve(self, v: np.ndarray) -> np.ndarray:
        """The fitted steady friction (Eq. 12) at v [m/s]."""
        p = self.parameters
        return steady_friction(
            np.asarray(v, dtype=float),
            p["friction.F_s"],
            p["friction.F_c"],
            p["friction.V_s"],
            p["friction.delta"],
            p["friction.sigma2"],
        )


def _pair_runs(
    runs: Sequence[Run], window: int, rel_tol: float, speed_tol: float, dc_gain: float | None
):
    items = []
    for k, run in enumerate(runs):
        label = f"[{k}] {run_label(run)}"
        Ts = sample_time(run.time, label=label)
        x, i = signal(run, "x"), current(run, dc_gain)
        w = min(window, max(len(x) // 20, 5))
        seg, v = steady_segment(x, Ts, window=w, rel_tol=rel_tol, label=label)
        items.append((label, x[seg], i[seg], v, run_load_mean(run)[0]))
    fw = sorted([it for it in items if it[3] > 0], key=lambda it: it[3])
    bw = sorted([it for it in items if it[3] < 0], key=lambda it: -it[3])
    pairs = []
    used: set[int] = set()
    for f in fw:
        cand = [(abs(abs(b[3]) - f[3]), j) for j, b in enumerate(bw) if j not in used]
        if not cand or min(cand)[0] > speed_tol * f[3]:
            raise ValueError(
                f"Stribeck: run {f[0]} (v = {f[3]:g} m/s) has no opposite run "
                f"within {100 * speed_tol:g} % of its speed"
            )
        j = min(cand)[1]
        used.add(j)
        pairs.append((f, bw[j]))
    left = [bw[j][0] for j in range(len(bw)) if j not in used]
    if left:
        raise ValueError(f"Stribeck: unpaired backward runs {left}")
    return pairs


def stribeck_points(
    runs: Sequence[Run],
    force_constant: MapSpec,
    cogging: MapSpec | None = None,
    grid_step: float = GRID_STEP,
    window: int = 201,
    rel_tol: float = 0.25,
    speed_tol: float = 0.1,
    resample: str = "bin",
    dc_gain: float | None = None,
) -> StribeckPoints:
    """Eq. 13 for every +-v pair of runs (K_f from ``force_constant``: FMU params or callable).

    ``cogging`` (params or callable), when given, adds the forward-backward asymmetry.
    Loads must be equal within a pair (they cancel in Eq. 13); they enter the asymmetry.
    ``resample='bin'`` (default) averages every sample of a 0.1 mm cell, so that the
    position mean uses all data; 'interp' is the paper's interpolation of Sec. 2.3.
    ``dc_gain``: for runs without a current column, i = dc_gain * u (the recording format).
    """
    pairs = _pair_runs(runs, window, rel_tol, speed_tol, dc_gain)
    if len(pairs) < 1:
        raise ValueError("Stribeck: no pair of runs")
    sp, fr, spread, asym, names = [], [], [], [], []
    for f, b in pairs:
        if abs(f[4] - b[4]) > 0.5:
            raise ValueError(
                f"Stribeck: runs {f[0]} and {b[0]} have different loads ({f[4]:g}, {b[4]:g} N)"
            )
        grid = common_grid(
            [(f[1].min(), f[1].max()), (b[1].min(), b[1].max())],
            grid_step,
            label=f"{f[0]} / {b[0]}",
        )
        i_f = to_grid(f[1], f[2], grid, resample, grid_step)
        i_b = to_grid(b[1], b[2], grid, resample, grid_step)
        Kf = eval_map(force_constant, "ripple", grid)
        F = 0.5 * Kf * (i_f - i_b)
        sp.append(0.5 * (f[3] - b[3]))
        fr.append(float(np.mean(F)))
        spread.append(float(np.std(F)))
        if cogging is not None:
            Fcg = eval_map(cogging, "cogging", grid)
            asym.append(float(np.mean(Kf * (i_f + i_b) - 2 * (Fcg + f[4]))))
        names.append((f[0], b[0]))
    return StribeckPoints(
        speed=np.array(sp),
        friction=np.array(fr),
        spread=np.array(spread),
        asymmetry=np.array(asym) if cogging is not None else None,
        pairs=names,
    )


def fit_stribeck(
    speed: np.ndarray, friction: np.ndarray, weights: np.ndarray | None = None
) -> tuple[dict[str, float], dict[str, float], np.ndarray]:
    """Nonlinear least-squares fit of Eq. 12 (v > 0) to points (speed [m/s], friction [N]).

    Returns parameters, standard errors (FMU names) and the residual model - data.
    Needs at least 6 points spanning the Stribeck region and the viscous range.
    """
    v = np.asarray(speed, dtype=float)
    F = np.asarray(friction, dtype=float)
    if np.any(v <= 0) or len(v) < 6:
        raise ValueError(f"Stribeck fit: need >= 6 points with v > 0, got {len(v)}")
    w = np.ones_like(v) if weights is None else np.asarray(weights, dtype=float)
    # starting values: Coulomb + viscous line through the fastest half, F_s from the slowest point
    hi = v >= np.median(v)
    sig0, Fc0 = np.polyfit(v[hi], F[hi], 1)
    sig0, Fc0 = max(sig0, 0.0), max(Fc0, 0.0)
    Fs0 = max(F[np.argmin(v)], Fc0 * 1.01)

    def resid(th):
        return w * (steady_friction(v, *th) - F)

    lb = [0.0, 0.0, v.min() * 1e-3, 0.05, 0.0]
    ub = [np.inf, np.inf, v.max() * 10, 10.0, np.inf]
    best = None
    for Vs0 in np.geomspace(v.min(), v.max(), 6):
        for d0 in (0.5, 1.0, 2.0):
            th0 = np.clip([Fs0, Fc0, Vs0, d0, sig0], np.array(lb) + 1e-12, np.array(ub) - 1e-12)
            sol = least_squares(resid, th0, bounds=(lb, ub), x_scale="jac")
            if best is None or sol.cost < best.cost:
                best = sol
    assert best is not None  # the grid of starts is not empty
    se = jacobian_stderr(np.asarray(best.jac), best.fun)
    params = {n: float(t) for n, t in zip(NAMES, best.x, strict=True)}
    return (
        params,
        {n: float(s) for n, s in zip(NAMES, se, strict=True)},
        steady_friction(v, *best.x) - F,
    )


def identify_stribeck(
    runs: Sequence[Run], force_constant: MapSpec, cogging: MapSpec | None = None, **kw
) -> StribeckFit:
    """Eq. 13 on the run pairs, then the fit of Eq. 12 (and the asymmetry line)."""
    pts = stribeck_points(runs, force_constant, cogging, **kw)
    params, se, r = fit_stribeck(pts.speed, pts.friction)
    asym = None
    if pts.asymmetry is not None and len(pts.speed) >= 3:
        A = np.column_stack((np.ones_like(pts.speed), pts.speed))
        th, s, _ = lstsq_with_stderr(A, pts.asymmetry)
        asym = {
            "asymmetry.dF": float(-th[0]),
            "asymmetry.dsigma2": float(-th[1]),
            "stderr.asymmetry.dF": float(s[0]),
            "stderr.asymmetry.dsigma2": float(s[1]),
        }
    return StribeckFit(
        parameters=params,
        stderr=se,
        points=pts,
        residual=r,
        rms_residual=float(np.sqrt(np.mean(r**2))),
        asymmetry=asym,
    )
