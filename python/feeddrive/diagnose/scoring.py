"""Held-out scoring of a candidate variant and the ambiguity rule.

The residual is coloured (friction, maps and the acceleration filter all act over many
samples), so in-sample fit says little about significance.  Each variant is fitted with
every block held out in turn (samples within a kernel length of the held-out block are left
out of the fit too) and predicts the held-out block.  Statistics:

- ``improvement``: 1 - SSE_heldout / SSE_before over all blocks (fraction of the residual's
  energy the variant removes on data it was not fitted to);
- ``t``: mean / standard error over blocks of the bounded per-block change
  rho_b = (SSE_before - SSE_heldout) / (SSE_before + SSE_heldout), in [-1, 1] (blocks, not
  samples, are the independent units; bounded, so that neither an effect that lives in a
  few regimes nor a block that holds almost no residual dominates the statistic), over the
  blocks where the candidate predicts something (:func:`informative`: a PRBS run added to
  a set must not dilute the evidence of the runs that show the effect).

A candidate is *significant* when improvement >= ``I_MIN`` and t >= ``T_MIN`` and the model
it identifies passes the FMU's parameter rules (``feeddrive.physics.compile``, run by the
ModelFile it builds); a refused one keeps its message in ``refused`` and its in-sample
improvement is -inf, so that neither the ranking nor the polish can pick it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import numpy as np
from scipy.optimize import nnls

from ..effects.candidate import Variant
from ..model_file import ModelFileError
from .context import Context

I_MIN = 0.05  #: minimum held-out share of the residual energy a named effect must remove
T_MIN = 2.5  #: minimum block t statistic (10 blocks: one-sided p ~ 0.017)
AMBIGUITY = 0.10  #: candidates within this share of the best's improvement are not separated
#: A block whose prediction energy is below this share of the strongest block's is left out
#: of the t statistic (:func:`informative`).
INFO_SHARE = 0.01


@dataclass
class Score:
    """Held-out statistics of one variant."""

    variant: Variant
    improvement: float  #: held-out fraction of residual energy removed
    t: float  #: t statistic of the per-block SSE reductions
    sse_before: np.ndarray  #: per block
    sse_after: np.ndarray  #: per block (held-out predictions)
    improvement_in_sample: float
    theta: np.ndarray  #: fitted on all data
    r_fit: np.ndarray  #: residual after the all-data fit (stacked)
    r_heldout: np.ndarray  #: residual of the held-out predictions (stacked)
    refused: str | None = None  #: why the identified model breaks a parameter rule

    @property
    def significant(self) -> bool:
        return self.refused is None and self.improvement >= I_MIN and self.t >= T_MIN

    @property
    def blocks_improved(self) -> int:
        return int(np.sum(self.sse_after < self.sse_before))


def _solve_gram(var: Variant, G: np.ndarray, c: np.ndarray, yy: float, n: int) -> np.ndarray:
    """Least squares from the normal equations G theta = c (column-scaled; NNLS when
    ``nonneg``; sum(theta) = 1 enforced by a heavy extra row when ``sum_to_one``)."""
    d = np.sqrt(np.clip(np.diag(G), 0.0, None))
    live = d > 1e-12 * max(float(d.max()), 1e-300)
    theta = np.zeros(len(c))
    if not np.any(live):
        return theta
    Gs = G[np.ix_(live, live)] / np.outer(d[live], d[live])
    cs = c[live] / d[live]
    if var.sum_to_one:
        w = 30.0 * np.sqrt(max(yy, 1e-18))
        row = w / d[live]
        Gs = Gs + np.outer(row, row)
        cs = cs + row * w
    if var.nonneg:
        # ||A t - y||^2 = t' G t - 2 c' t + const = ||L' t - L^-1 c||^2 with G = L L'
        L = np.linalg.cholesky(Gs + 1e-10 * np.eye(len(cs)))
        th, _ = nnls(L.T, np.linalg.solve(L, cs), maxiter=50 * len(cs))
    else:
        th = np.linalg.lstsq(Gs, cs, rcond=None)[0]
    theta[live] = th / d[live]
    return theta


#: A nuisance column (e.g. a free response from a run's start) is left out of a training
#: fit that holds less than this share of its energy: it lives in the held-out block.
NUISANCE_SEEN = 0.01


def _drop_unseen(
    Gt: np.ndarray, ct: np.ndarray, G: np.ndarray, k: int
) -> tuple[np.ndarray, np.ndarray]:
    """Zero the rows and columns of the last ``k`` (nuisance) columns that the training
    blocks barely see, so that they are not extrapolated into the held-out block."""
    d, dt = np.diag(G), np.diag(Gt)
    idx = [j for j in range(len(d) - k, len(d)) if dt[j] < NUISANCE_SEEN * d[j]]
    if not idx:
        return Gt, ct
    Gt, ct = Gt.copy(), ct.copy()
    Gt[idx, :] = 0.0
    Gt[:, idx] = 0.0
    ct[idx] = 0.0
    return Gt, ct


def score(ctx: Context, var: Variant) -> Score:
    """Held-out and in-sample statistics of ``var`` (see module docstring)."""
    r = ctx.r
    base = var.base if var.base is not None else 0.0
    y = r + base
    Phi = var.Phi
    B = ctx.blocks
    bounds = ctx.block_bounds
    Gb = [Phi[lo:hi].T @ Phi[lo:hi] for lo, hi in bounds]
    cb = [Phi[lo:hi].T @ y[lo:hi] for lo, hi in bounds]
    yb = [float(y[lo:hi] @ y[lo:hi]) for lo, hi in bounds]
    G, c, yy, n = cast(np.ndarray, sum(Gb)), cast(np.ndarray, sum(cb)), sum(yb), len(y)
    r_ho = np.empty_like(r)
    sb, sa = np.zeros(B), np.zeros(B)
    for b, (lo, hi) in enumerate(bounds):
        g = ctx.guard[b]
        Gt, ct, yt = G - Gb[b], c - cb[b], yy - yb[b]
        if g.size:
            Gt = Gt - Phi[g].T @ Phi[g]
            ct = ct - Phi[g].T @ y[g]
            yt = yt - float(y[g] @ y[g])
        if var.nuisance:
            Gt, ct = _drop_unseen(Gt, ct, G, var.nuisance)
        th = _solve_gram(var, Gt, ct, yt, n)
        e = y[lo:hi] - Phi[lo:hi] @ th
        r_ho[lo:hi] = e
        sb[b] = float(r[lo:hi] @ r[lo:hi])
        sa[b] = float(e @ e)
    theta = _solve_gram(var, G, c, yy, n)
    r_fit = y - Phi @ theta
    d = ((sb - sa) / np.maximum(sb + sa, 1e-300))[informative(Phi @ theta, bounds)]
    sd = float(np.std(d, ddof=1)) if d.size > 1 else 0.0
    t = (
        float(np.mean(d) / (sd / np.sqrt(d.size)))
        if sd > 0
        else (np.inf if d.size > 1 and np.mean(d) > 0 else 0.0)
    )
    tot = float(sb.sum())
    rr = float(r @ r)
    refused = admissible(var, theta)
    return Score(
        variant=var,
        improvement=1.0 - float(sa.sum()) / tot if tot > 0 else 0.0,
        t=t,
        sse_before=sb,
        sse_after=sa,
        improvement_in_sample=-np.inf
        if refused
        else 1.0 - float(r_fit @ r_fit) / rr
        if rr > 0
        else 0.0,
        theta=theta,
        r_fit=r_fit,
        r_heldout=r_ho,
        refused=refused,
    )


def informative(pred: np.ndarray, bounds: list[tuple[int, int]]) -> np.ndarray:
    """Blocks where the candidate's all-data prediction carries at least ``INFO_SHARE`` of
    the energy of its strongest block: a block where the candidate predicts nothing (a PRBS
    hold for a direction-dependent level, a run whose start state takes up a constant
    force) tells nothing about it and is left out of the t statistic."""
    pb = np.array([float(pred[lo:hi] @ pred[lo:hi]) for lo, hi in bounds])
    top = float(pb.max()) if pb.size else 0.0
    return pb >= INFO_SHARE * top if top > 0 else np.ones(len(bounds), dtype=bool)


def admissible(var: Variant, theta: np.ndarray) -> str | None:
    """None when the model ``var`` identifies with ``theta`` passes the FMU's rules, else the
    message naming the parameter (e.g. friction.sigma2 = -7135 out of range)."""
    try:
        var.to_model(theta)
    except ModelFileError as e:
        return e.problem
    return None


def separable(best: Score, other: Score) -> bool:
    """True when held-out data tell ``best`` from ``other`` apart: the improvements differ
    by more than ``AMBIGUITY`` of the best's and the per-block differences are consistent
    (t >= T_MIN)."""
    gap = best.improvement - other.improvement
    if gap <= AMBIGUITY * best.improvement:
        return False
    d = (other.sse_after - best.sse_after) / np.maximum(other.sse_after + best.sse_after, 1e-300)
    sd = float(np.std(d, ddof=1))
    t = float(np.mean(d) / (sd / np.sqrt(len(d)))) if sd > 0 else np.inf
    return t >= T_MIN or gap > 0.5 * best.improvement
