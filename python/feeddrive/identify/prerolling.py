"""Pre-rolling (pre-sliding) parameters of the GMS model (Sec. 2.4.4, Eqs. 15-18).

At low speed the GMS model reduces to the Maxwell-slip model (Eq. 15): element i is a spring
in series with a block of break-away force W_i = nu_i F_s and maximum spring extension
Delta_i = W_i / k_i; F_f = sum W_i Phi_i with Phi_i = u_i / Delta_i, u_i = x - zeta_i, while
|u_i| < Delta_i, else Phi_i = sgn(u_i) and zeta_i = x - sgn(u_i) Delta_i.

Procedure (two low-frequency periodic runs, a large and a small amplitude):

1. friction along each run from Eq. 1 with known maps and mass (``feeddrive.physics.eq1_friction``);
2. reversal points (scipy.signal.find_peaks on the position), displacement since reversal d,
   and the force change sgn * F (one free offset per half cycle), from the second reversal
   on (the first half cycle starts from an unknown state);
3. a continuous piecewise-linear fit of that force-displacement curve with free knots
   (knots placed greedily on a log grid, then refined jointly by scipy least_squares; the
   linear coefficients and per-half-cycle offsets by linear least squares).  After a reversal
   element i is fully reversed at d = 2 Delta_i, so each knot is 2 Delta_i;
4. Delta_N = (end of pre-rolling of the large amplitude)/2, the end being the first knot
   after which the curve is flat (slope < 2 % of the initial one), Delta_1..N-1 = the N-1
   knots of the small amplitude / 2;
5. W_i from Eq. 17 (on the small amplitude by default) by non-negative least squares with
   sum W_i = F_s (Eq. 18) imposed as a heavily weighted extra row (so W_N = F_s - sum W_i
   >= 0 too; the paper's plain least squares gave negative W_i), the Maxwell-slip model
   started at each run's second reversal, one constant force per run;
   nu_i = W_i / F_s, k_i = W_i / Delta_i (Eq. 16).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from itertools import groupby

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import least_squares, nnls
from scipy.signal import find_peaks

from ..data import Run
from ..paper import N_ELEMENTS_MAX
from ..physics import MapSpec, eq1_friction
from ..signals import run_label
from ._signals import current, signal


def maxwell_slip(
    x: np.ndarray, Delta: ArrayLike, W: ArrayLike | None = None, phi0: float | Sequence[float] = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """Maxwell-slip model (Eq. 15) along a position trajectory.

    Parameters
    ----------
    x : positions [m], in time order.
    Delta : maximum spring extension of each element [m] (> 0).
    W : break-away force of each element [N] (default: ones, i.e. F = sum Phi).
    phi0 : initial Phi_i (0 = virgin, +-1 = fully strained), scalar or per element.

    Returns
    -------
    F : sum_i W_i Phi_i [N], shape (n,).
    Phi : shape (n, N).
    """
    x = np.asarray(x, dtype=float)
    D = np.asarray(Delta, dtype=float)
    if np.any(D <= 0):
        raise ValueError(f"maxwell_slip: every Delta_i must be > 0, got {D.tolist()}")
    Wv = np.ones_like(D) if W is None else np.asarray(W, dtype=float)
    p0 = np.broadcast_to(np.asarray(phi0, dtype=float), D.shape)
    if np.any(np.abs(p0) > 1):
        raise ValueError(f"maxwell_slip: |phi0| must be <= 1, got {p0.tolist()}")
    Phi = np.empty((len(x), len(D)))
    xs = x.tolist()
    for j, (d, ph) in enumerate(zip(D.tolist(), p0.tolist(), strict=True)):
        zeta = xs[0] - ph * d if xs else 0.0
        col = []
        for xk in xs:
            u = xk - zeta
            if u > d:
                zeta = xk - d
                u = d
            elif u < -d:
                zeta = xk + d
                u = -d
            col.append(u / d)
        Phi[:, j] = col
    return Phi @ Wv, Phi


@dataclass
class HalfCycles:
    """Force-displacement data after each reversal of one run."""

    d: np.ndarray  #: displacement since the reversal [m] (>= 0)
    y: np.ndarray  #: sgn * F_f [N] (increases with d)
    cycle: np.ndarray  #: half-cycle index of each sample
    reversals: np.ndarray  #: sample indices of the reversals
    amplitude: float  #: half the median peak-to-peak travel [m]


@dataclass
class KnotFit:
    """Continuous piecewise-linear fit y = c_j + s0 d + sum beta_m max(0, d - t_m)."""

    knots: np.ndarray
    slopes: np.ndarray  #: slope on each of the len(knots)+1 pieces [N/m]
    rms: float


@dataclass
class PrerollingFit:
    """Identified pre-rolling parameters."""

    parameters: dict[str, float]  #: friction.N, friction.nu[1..10], friction.k[1..10] [N/m]
    Delta: np.ndarray  #: [m]
    W: np.ndarray  #: [N], all >= 0, sum = F_s
    nu: np.ndarray
    k: np.ndarray  #: [N/m]
    knots_small: KnotFit
    knots_large: KnotFit
    rms: dict[str, float]  #: 'large'/'small' -> force-displacement rms error [N]
    rms_relative: float  #: rms / F_s of the (first) run used for W
    offsets: dict[str, float]  #: 'large'/'small' -> fitted constant force [N]
    curves: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]] = field(default_factory=dict)
    #: 'large'/'small' -> (x, measured F_f, model F_f) on the fitted samples


def half_cycles(
    x: np.ndarray, F: np.ndarray, min_fraction: float = 0.3, skip: int = 0
) -> HalfCycles:
    """Split a periodic run at its reversals (extrema of x with prominence >= min_fraction
    of the total travel); samples before reversal number ``skip`` (0-based) and NaN forces
    are dropped (``reversals`` keeps every reversal found)."""
    x, F = np.asarray(x, dtype=float), np.asarray(F, dtype=float)
    span = np.nanmax(x) - np.nanmin(x)
    if span <= 0:
        raise ValueError("pre-rolling: the position does not move")
    hi, _ = find_peaks(x, prominence=min_fraction * span, plateau_size=1)
    lo, _ = find_peaks(-x, prominence=min_fraction * span, plateau_size=1)
    # maxima and minima must alternate: a dwell at a reversal with +-1 count of jitter gives
    # several equal extrema in a row - keep the middle one of each run
    kind = np.concatenate((np.ones(len(hi)), -np.ones(len(lo))))
    idx = np.concatenate((hi, lo))
    order = np.argsort(idx)
    idx, kind = idx[order], kind[order]
    rev_list: list[int] = []
    for sign, grp in groupby(zip(idx.tolist(), kind.tolist(), strict=True), key=lambda t: t[1]):
        members = [g[0] for g in grp]
        vals = [float(x[m]) for m in members]
        best = max(vals) if sign > 0 else min(vals)
        ext = [m for m, v in zip(members, vals, strict=True) if v == best]
        rev_list.append(ext[len(ext) // 2])
    rev = np.array(rev_list, dtype=int)
    if len(rev) < skip + 2:
        raise ValueError(f"pre-rolling: {len(rev)} reversals found, need at least {skip + 2}")
    ds, ys, cs = [], [], []
    for j, (r0, r1) in enumerate(zip(rev[skip:], np.append(rev[skip + 1 :], len(x)), strict=True)):
        seg = slice(r0, r1)
        sgn = np.sign(x[min(r1, len(x)) - 1] - x[r0]) or 1.0
        d = sgn * (x[seg] - x[r0])
        # up to the farthest point only (the last segment may run past an undetected reversal)
        ok = np.isfinite(F[seg]) & (np.arange(len(d)) <= np.argmax(d))
        ds.append(d[ok])
        ys.append(sgn * F[seg][ok])
        cs.append(np.full(ok.sum(), j))
    travel = np.abs(np.diff(x[rev]))
    return HalfCycles(
        d=np.concatenate(ds),
        y=np.concatenate(ys),
        cycle=np.concatenate(cs),
        reversals=rev,
        amplitude=float(np.median(travel)) / 2,
    )


def _basis(d: np.ndarray, knots: np.ndarray) -> np.ndarray:
    return np.column_stack([d] + [np.maximum(0.0, d - t) for t in knots])


def _demean(A: np.ndarray, cyc: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Subtract the per-half-cycle mean (projects out the free offsets c_j)."""
    A = np.atleast_2d(A.T).T
    means = np.stack([np.bincount(cyc, weights=A[:, c]) for c in range(A.shape[1])], 1)
    return A - means[cyc] / counts[cyc, None]


def _pl_residual(knots, d, yc, cyc, counts):
    A = _demean(_basis(d, knots), cyc, counts)
    # normal equations on norm-scaled columns (fast; the search calls this hundreds of
    # times), least squares when they are ill-conditioned (knots nearly coinciding)
    sc = np.linalg.norm(A, axis=0)
    sc[sc == 0] = 1.0
    As = A / sc
    G = As.T @ As
    if np.linalg.cond(G) < 1e10:
        beta = np.linalg.solve(G, As.T @ yc) / sc
    else:
        beta = np.linalg.lstsq(A, yc, rcond=None)[0]
    return yc - A @ beta, beta


def fit_knots(
    hc: HalfCycles, n_knots: int, d_max: float | None = None, n_grid: int = 60, decimate: int = 1
) -> KnotFit:
    """Free-knot continuous piecewise-linear fit of the force-displacement data.

    Knots are inserted greedily (best position on a log grid of ``n_grid`` points over
    (d_max/300, d_max)), then refined jointly by least_squares in log(d).
    """
    d, y = hc.d, hc.y
    dmax = float(np.max(d)) if d_max is None else float(d_max)
    sel = d <= dmax
    d, y, cyc = d[sel][::decimate], y[sel][::decimate], hc.cycle[sel][::decimate]
    _, cyc = np.unique(cyc, return_inverse=True)
    counts = np.bincount(cyc).astype(float)
    yc = _demean(y, cyc, counts)[:, 0]
    grid = np.geomspace(dmax / 300, dmax * 0.98, n_grid)
    knots: list[float] = []
    for _ in range(n_knots):
        costs = []
        for g in grid:
            if any(abs(np.log(g / t)) < 0.05 for t in knots):
                costs.append(np.inf)
                continue
            r, _ = _pl_residual(np.array(sorted(knots + [g])), d, yc, cyc, counts)
            costs.append(float(r @ r))
        knots.append(float(grid[int(np.argmin(costs))]))
        knots.sort()

    def res(logk):
        return _pl_residual(np.sort(np.exp(logk)), d, yc, cyc, counts)[0]

    sol = least_squares(
        res,
        np.log(knots),
        bounds=(np.log(dmax / 1000), np.log(dmax)),
        diff_step=np.full(len(knots), 1e-3),
    )
    kn = np.sort(np.exp(sol.x))
    r, beta = _pl_residual(kn, d, yc, cyc, counts)
    return KnotFit(knots=kn, slopes=np.cumsum(beta), rms=float(np.sqrt(np.mean(r**2))))


def fit_weights(
    segments: Sequence[tuple[np.ndarray, np.ndarray, float | Sequence[float]]],
    Delta: ArrayLike,
    F_s: float,
    fit_offset: bool = True,
    nonnegative: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """W_1..W_N for given Delta_i from friction samples along position trajectories.

    Parameters
    ----------
    segments : (x, F_f, phi0) per run segment: positions, friction [N] (NaN skipped) and the
        initial Phi_i of that segment (scalar or per element).
    Delta : Delta_i [m].
    F_s : static friction; sum W_i = F_s (Eq. 18).
    fit_offset : one free constant force per segment (it absorbs the unknown state of
        elements that never saturate in that segment, and any constant force bias).
    nonnegative : True: NNLS with sum W_i = F_s imposed by a heavily weighted extra row, so
        every W_i >= 0 including W_N.  False: the paper's plain least squares on Eq. 17
        (W_N from Eq. 18), which may return negative W_i.

    Returns
    -------
    W : [N]; offsets : one per segment [N] (zeros without fit_offset).
    """
    D = np.asarray(Delta, dtype=float)
    N, S = len(D), len(segments)
    rows, rhs, seg_of = [], [], []
    for j, (x, F, phi0) in enumerate(segments):
        _, Phi = maxwell_slip(x, D, phi0=phi0)
        ok = np.isfinite(F)
        rows.append(Phi[ok])
        rhs.append(np.asarray(F)[ok])
        seg_of.append(np.full(ok.sum(), j))
    A, b, sj = np.vstack(rows), np.concatenate(rhs), np.concatenate(seg_of)
    E = (
        (sj[:, None] == np.arange(S)[None, :]).astype(float)
        if fit_offset
        else np.zeros((len(b), 0))
    )
    if not nonnegative:
        B = A[:, : N - 1] - A[:, [N - 1]]  # Eq. 17
        th, *_ = np.linalg.lstsq(np.hstack((B, E)), b - F_s * A[:, N - 1], rcond=None)
        W = np.append(th[: N - 1], F_s - np.sum(th[: N - 1]))
        return W, th[N - 1 :] if fit_offset else np.zeros(S)
    Aa = np.hstack((A, E, -E))  # offsets as +/- pairs
    M = 1e4 * np.sqrt(len(b))
    row = np.zeros(Aa.shape[1])
    row[:N] = M
    sol, _ = nnls(np.vstack((Aa, row)), np.append(b, M * F_s), maxiter=50 * Aa.shape[1])
    W = sol[:N].copy()
    W[-1] = max(F_s - float(np.sum(W[:-1])), 0.0)  # Eq. 18 exactly
    off = sol[N : N + E.shape[1]] - sol[N + E.shape[1] :] if fit_offset else np.zeros(S)
    return W, off


def identify_prerolling(
    large: Run,
    small: Run,
    params: Mapping[str, float],
    N: int = 5,
    force_constant: MapSpec | None = None,
    cogging: MapSpec | None = None,
    window: int = 41,
    current_timing: str = "held",
    start: str = "reversal",
    skip_reversals: int = 1,
    phi0: float | Sequence[float] = 0.0,
    fit_offset: bool = True,
    fit_runs: str = "small",
    decimate: int = 2,
    flat_fraction: float = 0.02,
    dc_gain: float | None = None,
) -> PrerollingFit:
    """Pre-rolling parameters from a large- and a small-amplitude periodic run.

    Parameters
    ----------
    large, small : low-frequency periodic runs (columns time, x, i; F_load when present).
        The small amplitude must exceed Delta_{N-1} and stay below Delta_N.
    params : FMU parameters: m, friction.F_s (and the maps unless given separately).
    N : number of elements (2..10).
    window, current_timing : Eq. 1 friction (see ``feeddrive.physics.eq1_friction``).
    start : 'reversal' (default): the model starts at reversal number ``skip_reversals``
        with every element strained in the direction of the motion before it.  After a full
        half cycle (travel 2A) that holds for every element with Delta_i <= A; the others
        stay in their linear range, where their unknown state is a constant force taken up
        by the offset.  The state before a recording (e.g. after a hold against cogging) is
        thus never needed.  'record': from the first sample with ``phi0``.
    skip_reversals : reversals skipped (by the model start and by the knot fits) - 1 skips
        the first half cycle, whose start state depends on the unknown history.
    phi0 : initial Phi_i for start='record' (0: virgin).
    fit_offset : one constant force per run (see :func:`fit_weights`).
    fit_runs : 'small' (default), 'both' or 'large' - runs used for the W_i least squares.
        The small amplitude is slow enough for s(v) ~ F_s (the assumption of Eq. 15); in the
        large one the sliding plateau is s(v) + sigma2 v < F_s, which the Maxwell-slip model
        with sum W_i = F_s cannot follow.
    decimate : sample step of the knot search.
    flat_fraction : the end of pre-rolling of the large amplitude is the first knot after which
        the slope is below this fraction of the initial (all elements stuck) slope; the
        large-amplitude curve gets N + 1 knots so that the sliding tail (Stribeck, viscous)
        has one of its own.
    dc_gain : for runs without a current column, i = dc_gain * u (the recording format).
    """
    if not 2 <= N <= N_ELEMENTS_MAX:
        raise ValueError(f"pre-rolling: N must be in 2..{N_ELEMENTS_MAX}, got {N}")
    Kf = force_constant if force_constant is not None else params
    Fcg = cogging if cogging is not None else params
    F_s = float(params["friction.F_s"])
    use = {"both": ("large", "small"), "small": ("small",), "large": ("large",)}.get(fit_runs)
    data = {
        tag: _run_friction(
            run, tag, params["m"], Kf, Fcg, window, current_timing, skip_reversals, dc_gain
        )
        for tag, run in (("large", large), ("small", small))
    }
    Delta, kl, ks = _element_travels(data, N, decimate, flat_fraction)
    if use is None:
        raise ValueError(
            f"pre-rolling: fit_runs must be 'both', 'small' or 'large', got {fit_runs!r}"
        )
    segs = {
        tag: _model_segment(data[tag], tag, start, skip_reversals, phi0)
        for tag in ("large", "small")
    }
    W, offs = fit_weights([segs[t] for t in use], Delta, F_s, fit_offset=fit_offset)
    nu, k = W / F_s, W / Delta
    rms, curves, offsets = _fitted_curves(segs, use, offs, Delta, W, fit_offset)
    return PrerollingFit(
        parameters=_element_parameters(N, nu, k, W),
        Delta=Delta,
        W=W,
        nu=nu,
        k=k,
        knots_small=ks,
        knots_large=kl,
        rms=rms,
        rms_relative=rms[use[0]] / F_s,
        offsets=offsets,
        curves=curves,
    )


def _run_friction(
    run: Run,
    tag: str,
    m: float,
    Kf: MapSpec,
    Fcg: MapSpec,
    window: int,
    current_timing: str,
    skip_reversals: int,
    dc_gain: float | None,
) -> tuple[str, np.ndarray, np.ndarray, HalfCycles]:
    """Step 1: the run's label, position, Eq. 1 friction and its half cycles."""
    x = signal(run, "x")
    F_load = run.F_load if run.F_load is not None else 0.0
    F, _, _, _ = eq1_friction(
        run.time, x, current(run, dc_gain), m, Kf, Fcg, F_load, window, current_timing
    )
    try:
        hc = half_cycles(x, F, skip=skip_reversals)
    except ValueError as e:
        raise ValueError(f"{run_label(run)} ({tag} amplitude): {e}") from None
    return run_label(run), x, F, hc


def _element_travels(data: dict, N: int, decimate: int, flat_fraction: float):
    """Steps 2-3: the knots of both amplitudes and the element travels Delta_1..N from them
    (the small amplitude's N - 1 knots, the large one's end of pre-rolling)."""
    A_l, A_s = data["large"][3].amplitude, data["small"][3].amplitude
    if A_s >= A_l:
        raise ValueError(
            f"pre-rolling: the 'small' run's amplitude {A_s:g} m is not below the "
            f"'large' one's {A_l:g} m"
        )
    kl = fit_knots(data["large"][3], N + 1, decimate=decimate)
    ks = fit_knots(data["small"][3], N - 1, decimate=decimate)
    flat = np.flatnonzero(np.abs(kl.slopes[1:]) < flat_fraction * abs(kl.slopes[0]))
    if len(flat) == 0:
        raise ValueError(
            f"pre-rolling: the large amplitude ({A_l:g} m) never leaves pre-rolling "
            f"(no slope below {flat_fraction:g} of the initial one)"
        )
    Delta = np.append(ks.knots / 2, kl.knots[flat[0]] / 2)
    if np.any(np.diff(Delta) <= 0):
        raise ValueError(
            f"pre-rolling: Delta not increasing ({Delta.tolist()} m): the small "
            f"amplitude ({A_s:g} m) must exceed Delta_(N-1) and stay below Delta_N"
        )
    return Delta, kl, ks


def _model_segment(
    run_data: tuple, tag: str, start: str, skip_reversals: int, phi0: float | Sequence[float]
) -> tuple[np.ndarray, np.ndarray, float | Sequence[float]]:
    """Step 4: where the Maxwell-slip model starts on a run, (x, F, initial state)."""
    _, x, F, hc = run_data
    if start == "record":
        return x, F, phi0
    if start != "reversal":
        raise ValueError(f"pre-rolling: start must be 'reversal' or 'record', got {start!r}")
    r0 = int(hc.reversals[skip_reversals])
    before = int(hc.reversals[skip_reversals - 1]) if skip_reversals > 0 else 0
    direction = float(np.sign(x[r0] - x[before]))  # of the motion into r0
    if direction == 0:
        raise ValueError(
            f"pre-rolling: no motion before reversal {skip_reversals} of the {tag} run"
        )
    return x[r0:], F[r0:], direction


def _fitted_curves(
    segs: dict, use: tuple[str, ...], offs, Delta: np.ndarray, W: np.ndarray, fit_offset: bool
) -> tuple[dict, dict, dict]:
    """Step 6: the model along each run with its offset, the rms misfit and the curves."""
    rms, curves, offsets = {}, {}, {}
    for tag in ("large", "small"):
        x, F, p0 = segs[tag]
        model, _ = maxwell_slip(x, Delta, W, phi0=p0)
        ok = np.isfinite(F)
        if tag in use:
            off = offs[use.index(tag)]
        else:  # a run not used for W: its own offset (the mean misfit)
            off = float(np.mean(F[ok] - model[ok])) if fit_offset else 0.0
        rms[tag] = float(np.sqrt(np.mean((F[ok] - model[ok] - off) ** 2)))
        curves[tag] = (x[ok], F[ok], model[ok] + off)
        offsets[tag] = float(off)
    return rms, curves, offsets


def _element_parameters(N: int, nu: np.ndarray, k: np.ndarray, W: np.ndarray) -> dict[str, float]:
    """The FMU parameters of the elements (unused slots at the FMU's defaults)."""
    params_out: dict[str, float] = {"friction.N": N}
    for j in range(1, N_ELEMENTS_MAX + 1):
        params_out[f"friction.nu[{j}]"] = float(nu[j - 1]) if j <= N else 0.0
        # an element with W_i = 0 is inert whatever k_i: give it the FMU's unused-slot value
        params_out[f"friction.k[{j}]"] = float(k[j - 1]) if j <= N and W[j - 1] > 0 else 1.0e5
    return params_out
