"""Compliance fit shared by identification and diagnosis: the load's natural frequency f,
damping ratio zeta and mass m2 from filtered accelerations and a rigid model's force residual
(:func:`fit_compliance`; the method in :mod:`feeddrive.identify.compliance`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from ..physics import load_acceleration, load_free_response
from ..physics.compliance import F_RANGE

#: Frequency grid [Hz] and damping-ratio grid of the search.
F_GRID = tuple(np.geomspace(F_RANGE[0], F_RANGE[1], 13).tolist())
ZETA_GRID = (0.01, 0.03, 0.1, 0.3, 1.0)
ZETA_RANGE = (0.003, 2.0)
#: Stride of the samples the search evaluates (filtered signals are smooth).
SEARCH_STRIDE = 2


@dataclass
class ComplianceFit:
    """The fitted resonance and the energy it explains."""

    f: float  #: natural frequency of the load on its spring [Hz]
    zeta: float  #: damping ratio [1]
    m2: float  #: load mass [kg]
    dm: float  #: change of the (slide) mass fitted with it [kg] (0 if not fitted)
    explained: float  #: share of the residual energy the fit removes
    #: share a mass change alone removes (the f -> inf limit; with the ``nuisance`` columns)
    rigid_explained: float
    n_used: int


def _columns(
    a_runs: list[np.ndarray], Ts: list[float], f: float, zeta: float, masks: list[np.ndarray]
) -> np.ndarray:
    return np.concatenate(
        [load_acceleration(a, T, f, zeta)[m] for a, T, m in zip(a_runs, Ts, masks, strict=True)]
    )


def start_columns(
    a_runs: list[np.ndarray], Ts: list[float], f: float, zeta: float, masks: list[np.ndarray]
) -> np.ndarray:
    """(N, 2 n_runs) free responses of the load from each run's first filtered sample (zero
    in the other runs' rows): the load's state there is unknown (module docstring)."""
    n = [int(m.sum()) for m in masks]
    out = np.zeros((sum(n), 2 * len(n)))
    k = 0
    for j, (a, T, m) in enumerate(zip(a_runs, Ts, masks, strict=True)):
        out[k : k + n[j], 2 * j : 2 * j + 2] = np.nan_to_num(load_free_response(a, T, f, zeta)[m])
        k += n[j]
    return out


def nuisance_columns(nuisance: list[np.ndarray | None], masks: list[np.ndarray]) -> np.ndarray:
    """(N, k) per-run nuisance columns (each run's rows only, its usable samples) stacked
    block-diagonally; a run with None adds no column."""
    n = [int(m.sum()) for m in masks]
    parts = [
        np.asarray(B, dtype=float).reshape(len(m), -1)[m]
        if B is not None
        else np.zeros((int(m.sum()), 0))
        for B, m in zip(nuisance, masks, strict=True)
    ]
    out = np.zeros((sum(n), sum(p.shape[1] for p in parts)))
    k = c = 0
    for j, p in enumerate(parts):
        out[k : k + n[j], c : c + p.shape[1]] = np.nan_to_num(p)
        k, c = k + n[j], c + p.shape[1]
    return out[:, np.any(out != 0.0, axis=0)]


def _explained(A: np.ndarray, y: np.ndarray, stride: int) -> tuple[float, np.ndarray]:
    """Energy of y explained by the columns of A (normal equations) and the coefficients."""
    A, y = A[::stride], y[::stride]
    # einsum, not BLAS: a 1-2 column Gram matrix is cheaper without the thread pool
    G, c = np.einsum("ij,ik->jk", A, A), np.einsum("ij,i->j", A, y)
    th = np.linalg.lstsq(G, c, rcond=None)[0]
    return float(c @ th), th


def fit_compliance(
    a_runs: list[np.ndarray],
    y_runs: list[np.ndarray],
    Ts: list[float],
    fit_mass: bool = False,
    stride: int = SEARCH_STRIDE,
    nuisance: list[np.ndarray | None] | None = None,
) -> ComplianceFit:
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
        raise ValueError(
            f"fit_compliance: {y.size} usable samples with acceleration; need >= 100 "
            "and a motion that accelerates"
        )
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

    opt = minimize(
        neg,
        [math.log(grid[0]), math.log(grid[1])],
        method="Nelder-Mead",
        options={"xatol": 4e-3, "fatol": 1e-6 * yy, "maxiter": 80},
    )
    f = float(np.clip(np.exp(opt.x[0]), *F_RANGE))
    z = float(np.clip(np.exp(opt.x[1]), *ZETA_RANGE))
    if -opt.fun < expl(*grid):
        f, z = grid
    e, th = _explained(design(f, z), y, 1)
    rigid, _ = _explained(np.column_stack([a, B]), y, 1)
    return ComplianceFit(
        f=f,
        zeta=z,
        m2=float(th[0]),
        dm=float(th[1]) if fit_mass else 0.0,
        explained=e / yy if yy > 0 else 0.0,
        rigid_explained=rigid / yy if yy > 0 else 0.0,
        n_used=int(y.size),
    )
