"""Compliance (effect ``compliance``): the load's natural frequency f, damping ratio zeta and
mass m2 from the force residual of a rigid model along measured runs.

With the encoder on the slide and a load m2 on a spring-damper (``feeddrive.physics.compliance``)
Eq. 1 of the slide reads ``m a = F_slide - m2 a2`` with ``a2 = H(s) a``,
``H(s) = (2 zeta w s + w^2) / (s^2 + 2 zeta w s + w^2)``.  Filtered with the acceleration
estimator's kernel K (which commutes with H), the rigid model's residual
``y = K F_slide - m a_K`` is therefore

    y = m2 H(s) a_K  (+ dm a_K when the model's mass is off too),

plus the load's free response from each run's first filtered sample (its state there, half a
kernel into the run, is not measured: two nuisance coefficients per run), plus what a change
of the run's estimated GMS start forces makes of the friction over its first samples (with
pre-rolling on: :mod:`feeddrive.physics.gms_start` estimates them on the rigid residual,
where the load's own response at the start is still in it, so they are free again here, one
nuisance coefficient per element and run, their sensitivity ``GMSStart.basis``; fixed at the
rigid estimate, the start forces take up part of the load's first oscillations and bias its
damping), linear in (m2, dm) for fixed (f, zeta): a variable-projection fit, a grid over
f in [20, 200] Hz (the FMU's range) and zeta in [0.01, 1] searched by the explained energy,
the best point refined by Nelder-Mead in (log f, log zeta).  Excitation must reach f: the
steps of a trapezoidal move's acceleration (point-to-point moves) or a PRBS do; a slow
sinusoid does not (the load then only adds mass).  The Savitzky-Golay window bounds what can
be seen: its kernel attenuates f above about (polyorder + 1) / (3.2 window Ts).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize

from ..data import Run
from ..physics import (
    DEFAULT_V_STICK,
    applied_force,
    compile,
    force_residual,
    friction_velocity,
    gms_force,
    held_current,
    karnopp_friction,
    load_acceleration,
    load_free_response,
    measured_motion,
    run_load,
    started_friction,
)
from ..physics.compliance import F_RANGE
from ..physics.params import HasFmuParameters
from ..signals import odd_window, run_label, sample_time

#: Frequency grid [Hz] and damping-ratio grid of the search.
F_GRID = tuple(np.geomspace(F_RANGE[0], F_RANGE[1], 13).tolist())
ZETA_GRID = (0.01, 0.03, 0.1, 0.3, 1.0)
ZETA_RANGE = (0.003, 2.0)
#: Stride of the samples the search evaluates (filtered signals are smooth).
SEARCH_STRIDE = 2


@dataclass
class ComplianceFit:
    """The fitted resonance and the energy it explains."""

    f: float                    #: natural frequency of the load on its spring [Hz]
    zeta: float                 #: damping ratio [1]
    m2: float                   #: load mass [kg]
    dm: float                   #: change of the (slide) mass fitted with it [kg] (0 if not fitted)
    explained: float            #: share of the residual energy the fit removes
    #: share a mass change alone removes (the f -> inf limit; with the ``nuisance`` columns)
    rigid_explained: float
    n_used: int


def _columns(a_runs: list[np.ndarray], Ts: list[float], f: float, zeta: float,
             masks: list[np.ndarray]) -> np.ndarray:
    return np.concatenate([load_acceleration(a, T, f, zeta)[m] for a, T, m in zip(a_runs, Ts, masks, strict=True)])


def start_columns(a_runs: list[np.ndarray], Ts: list[float], f: float, zeta: float,
                  masks: list[np.ndarray]) -> np.ndarray:
    """(N, 2 n_runs) free responses of the load from each run's first filtered sample (zero
    in the other runs' rows): the load's state there is unknown (module docstring)."""
    n = [int(m.sum()) for m in masks]
    out = np.zeros((sum(n), 2 * len(n)))
    k = 0
    for j, (a, T, m) in enumerate(zip(a_runs, Ts, masks, strict=True)):
        out[k:k + n[j], 2 * j:2 * j + 2] = np.nan_to_num(load_free_response(a, T, f, zeta)[m])
        k += n[j]
    return out


def nuisance_columns(nuisance: list[np.ndarray | None], masks: list[np.ndarray]) -> np.ndarray:
    """(N, k) per-run nuisance columns (each run's rows only, its usable samples) stacked
    block-diagonally; a run with None adds no column."""
    n = [int(m.sum()) for m in masks]
    parts = [np.asarray(B, dtype=float).reshape(len(m), -1)[m] if B is not None
             else np.zeros((int(m.sum()), 0)) for B, m in zip(nuisance, masks, strict=True)]
    out = np.zeros((sum(n), sum(p.shape[1] for p in parts)))
    k = c = 0
    for j, p in enumerate(parts):
        out[k:k + n[j], c:c + p.shape[1]] = np.nan_to_num(p)
        k, c = k + n[j], c + p.shape[1]
    return out[:, np.any(out != 0.0, axis=0)]


def _explained(A: np.ndarray, y: np.ndarray, stride: int) -> tuple[float, np.ndarray]:
    """Energy of y explained by the columns of A (normal equations) and the coefficients."""
    A, y = A[::stride], y[::stride]
    # einsum, not BLAS: a 1-2 column Gram matrix is cheaper without the thread pool
    G, c = np.einsum("ij,ik->jk", A, A), np.einsum("ij,i->j", A, y)
    th = np.linalg.lstsq(G, c, rcond=None)[0]
    return float(c @ th), th


def fit_compliance(a_runs: list[np.ndarray], y_runs: list[np.ndarray], Ts: list[float],
                   fit_mass: bool = False, stride: int = SEARCH_STRIDE,
                   nuisance: list[np.ndarray | None] | None = None) -> ComplianceFit:
    """f, zeta, m2 (and dm when ``fit_mass``) from per-run filtered accelerations ``a_runs``
    [m/s^2] and rigid-model residuals ``y_runs`` [N] (NaN samples are left out).

    ``nuisance``: per run, (n, k) columns [N per unit] of other unknowns the residual holds
    (the GMS start forces' ``GMSStart.full_basis``), fitted jointly with free coefficients,
    or None.

    Raises ValueError when fewer than 100 samples are usable or nothing is excited.
    """
    masks = [np.isfinite(a) & np.isfinite(y) for a, y in zip(a_runs, y_runs, strict=True)]
    y = np.concatenate([np.asarray(yr)[m] for yr, m in zip(y_runs, masks, strict=True)])
    a = np.concatenate([np.asarray(ar)[m] for ar, m in zip(a_runs, masks, strict=True)])
    if y.size < 100 or not np.any(a != 0):
        raise ValueError(f"fit_compliance: {y.size} usable samples with acceleration; need >= 100 "
                         "and a motion that accelerates")
    yy = float(y @ y)
    B = nuisance_columns(nuisance if nuisance is not None else [None] * len(masks), masks)

    def design(f: float, z: float) -> np.ndarray:
        c = _columns(a_runs, Ts, f, z, masks)
        cols = [c, a] if fit_mass else [c]
        return np.column_stack(cols + [start_columns(a_runs, Ts, f, z, masks), B])

    def expl(f: float, z: float) -> float:
        return _explained(design(f, z), y, stride)[0]

    grid = max(((f, z) for f in F_GRID for z in ZETA_GRID), key=lambda p: expl(*p))

    def neg(u: np.ndarray) -> float:
        f = float(np.clip(np.exp(u[0]), *F_RANGE))
        z = float(np.clip(np.exp(u[1]), *ZETA_RANGE))
        return -expl(f, z)

    opt = minimize(neg, [math.log(grid[0]), math.log(grid[1])], method="Nelder-Mead",
                   options={"xatol": 4e-3, "fatol": 1e-6 * yy, "maxiter": 80})
    f = float(np.clip(np.exp(opt.x[0]), *F_RANGE))
    z = float(np.clip(np.exp(opt.x[1]), *ZETA_RANGE))
    if -opt.fun < expl(*grid):
        f, z = grid
    e, th = _explained(design(f, z), y, 1)
    rigid, _ = _explained(np.column_stack([a, B]), y, 1)
    return ComplianceFit(f=f, zeta=z, m2=float(th[0]), dm=float(th[1]) if fit_mass else 0.0,
                         explained=e / yy if yy > 0 else 0.0,
                         rigid_explained=rigid / yy if yy > 0 else 0.0, n_used=int(y.size))


@dataclass
class RigidResidual:
    """The rigid model's residual along one run and what it was computed with."""

    a: np.ndarray               #: filtered measured acceleration [m/s^2] (NaN near the ends)
    r: np.ndarray               #: residual of the model without its compliance [N]
    Ts: float                   #: sample interval [s]
    #: (n, N) the filtered friction's change per newton of each estimated GMS start force
    #: (zeros once the start no longer acts), or None (pre-rolling off)
    start_basis: np.ndarray | None = field(default=None)


def rigid_parts(run: Run, model: HasFmuParameters, window_s: float = 0.02,
                polyorder: int = 3) -> RigidResidual:
    """The filtered measured acceleration and the residual of ``model`` *without* its
    compliance, ``K (K_f(x) i - F_cg - F_load - offset - F_f) - m a_K`` (GMS friction along
    the measured motion with pre-rolling on, started from the element forces that best
    explain the first samples, :func:`feeddrive.physics.started_friction`, with their
    sensitivity; else Eq. 12 with Karnopp stiction).  The run needs a measured current
    ``i``."""
    label = run_label(run)
    if run.i is None:
        raise ValueError(f"{label}: identify_compliance needs a measured current column i")
    P = compile(model)
    Ts = sample_time(run.time, label=label)
    x = np.asarray(run.x, dtype=float)
    w = odd_window(int(round(window_s / Ts)), run.n)
    v, a, K = measured_motion(x, Ts, w, polyorder)
    F_load, _ = run_load(run)
    F_app = applied_force(P.K_f(x) * held_current(run.i), P.F_cg(x), F_load, P.F_offset)
    if P.prerolling:
        v_f = friction_velocity(x, Ts, w, polyorder)
        F_f = gms_force(x, v_f, Ts, P.friction)
        _, start, r = started_friction(x, v_f, Ts, P.friction,
                                       force_residual(F_app, F_f, a, P.m, K), K, F_f)
        basis = start.full_basis(len(x)) if start.basis is not None else None
        return RigidResidual(a, r, Ts, basis)
    F_f, _ = karnopp_friction(v, F_app, P.friction, DEFAULT_V_STICK)
    return RigidResidual(a, force_residual(F_app, F_f, a, P.m, K), Ts)


def rigid_residual(run: Run, model: HasFmuParameters, window_s: float = 0.02,
                   polyorder: int = 3) -> tuple[np.ndarray, np.ndarray, float]:
    """(a_K, y, Ts) of :func:`rigid_parts`."""
    p = rigid_parts(run, model, window_s, polyorder)
    return p.a, p.r, p.Ts


def identify_compliance(runs: list[Run], model: HasFmuParameters, fit_mass: bool = False,
                        window_s: float = 0.02) -> ComplianceFit:
    """f, zeta, m2 (module docstring) from measured runs (encoder on the slide) and a model of
    the rest of the drive (its own compliance, if any, is ignored): :func:`rigid_parts` per
    run, then :func:`fit_compliance` over all of them, the GMS start forces refitted with
    the load."""
    if not runs:
        raise ValueError("identify_compliance: no runs given")
    parts = [rigid_parts(run, model, window_s) for run in runs]
    return fit_compliance([p.a for p in parts], [p.r for p in parts], [p.Ts for p in parts],
                          fit_mass=fit_mass, nuisance=[p.start_basis for p in parts])
