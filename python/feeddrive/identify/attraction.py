"""Attraction parameter C of the GMS slip phase (Sec. 2.4.3, Eq. 14).

From a run at variable speed that never reverses (all elements slipping), with the maps, the
mass and the Stribeck parameters known, the friction force follows from Eq. 1,

    F_f = K_f(x) i - F_cg(x) - F_e - m a,     G = F_f - sigma2 v = sum F_i,

and Eq. 14 reads dG/dt = C sgn(v) (1 - G / s(v)) = (S - |G|) / tau with the slip relaxation
time tau = S(|v|)/C.  Two estimates are computed:

- equation error (the paper's least squares): dG/dt and G from Savitzky-Golay filtering; C
  by least squares of dG/dt on r = 1 - G/s(v), and kappa = 1/C by least squares of r on dG/dt.
  Both suffer from noise in their regressor (errors in variables): the first underestimates C
  when the lag is small, the second overestimates it when C is small.  They are reported as
  diagnostics.
- output error (returned): G simulated from s(v(t)) by the exact first-order-hold solution
  of Eq. 14 with parameter kappa = 1/C >= 0 and free initial value, filtered like the data,
  fitted to the measured G: a scan of kappa over 0 and 1e-8..10 s/N (initial value solved
  linearly), bounded refinement (minimize_scalar), then scipy least_squares on both for the
  Jacobian.  Noise then enters only the output, and
  kappa = 0 (instantaneous slip, C = inf) is inside the parameter range.

Resolution.  The information on C is the frictional lag G - s(v) ~ -tau ds/dt, a force of
(S/C)|dS/dt|; S changes only below ~10 V_s, so the run must sweep through that range quickly.
From 0.5 ms data with 100 nm quantisation it is the force noise after the differentiator,
not the sample time, that limits C: C is resolved while kappa = 1/C exceeds z standard
errors, i.e. up to C_max = 1 / (z se(kappa)) (``C_resolvable_max``, stated for each run).
Measured on synthetic closed-loop sweeps v = 6 +- 5 mm/s at 4 Hz, 2 s, 2 mA current noise:
se(kappa) ~ 5e-6 s/N, so C = 1.08e4 N/s (tau ~ 2 ms) comes out within ~10 % and C is
resolvable up to ~1e5 N/s (tau ~ 0.2 ms, half a sample); a slip with no lag at all gives
"C >= ~1e5 N/s".  The literal C = 10.8 N/s (tau ~ 2 s) needs a run of several tau (8 s at
0.5 Hz gives ~1 %).  When kappa is not significantly > 0 the result is the bound
"C >= C_lower, frictional lag below resolution" and ``resolved`` is False.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares, minimize_scalar

from ..data import Run
from ..physics import FrictionCurve, MapSpec, eq1_friction
from ..signals import apply_kernel, run_label
from ._signals import current, jacobian_stderr, signal


@dataclass
class AttractionFit:
    """C from Eq. 14 with its resolution."""

    parameters: dict[str, float]  #: friction.C [N/s] (the lower bound when not resolved)
    stderr: dict[str, float]  #: friction.C (delta method), kappa = 1/C [s/N]
    resolved: bool
    C: float  #: output-error estimate (inf when kappa = 0)
    C_interval: tuple[float, float]  #: ~95 % interval from kappa +- z se
    C_lower: float  #: lower end of the interval
    C_resolvable_max: float  #: 1/(z se(kappa)): the largest C this run can tell from inf
    C_equation_error: float  #: paper's LS, dG/dt on r
    C_equation_error_kappa: float  #: LS of r on dG/dt, inverted
    message: str
    rms_residual: float  #: output-error residual [N]
    n_used: int
    lag_rms: float  #: rms of the fitted lag G - s(v) [N] (0 when unresolved)


def _level(v: np.ndarray, p: Mapping[str, float]) -> np.ndarray:
    """s(v) with the FMU's asymmetry applied for v < 0."""
    return FrictionCurve.from_params(p).sliding(v)


def simulate_lag(s: np.ndarray, kappa: float, G0: float, Ts: float) -> np.ndarray:
    """Eq. 14 summed over slipping elements, dG/dt = (s - G) / (kappa |s|), s linear between
    samples (exact first-order-hold solution); kappa = 1/C, kappa = 0 gives G = s."""
    s = np.asarray(s, dtype=float)
    G = np.empty_like(s)
    G[0] = G0
    if kappa <= 0:
        G[1:] = s[1:]
        return G
    tau = kappa * 0.5 * (np.abs(s[1:]) + np.abs(s[:-1]))
    e = np.exp(-Ts / tau)
    p = s - np.concatenate((tau * np.diff(s) / Ts, [0.0]))  # particular solution at k (left)
    q = s[1:] - tau * np.diff(s) / Ts  # particular solution at k+1
    # G[k+1] = q[k] + (G[k] - p[k]) e[k]   (plain floats: a Python loop over lists is fast)
    out = [float(G0)]
    g = float(G0)
    for ek, pk, qk in zip(e.tolist(), p[:-1].tolist(), q.tolist(), strict=True):
        g = qk + (g - pk) * ek
        out.append(g)
    G[:] = out
    return G


def fit_attraction(
    time: np.ndarray,
    x: np.ndarray,
    i: np.ndarray,
    params: Mapping[str, float],
    force_constant: MapSpec | None = None,
    cogging: MapSpec | None = None,
    F_load: np.ndarray | float = 0.0,
    window: int = 41,
    v_min: float = 2e-4,
    x_skip: float = 5e-4,
    z: float = 2.0,
    current_timing: str = "held",
) -> AttractionFit:
    """C from a non-reversing run; see the module docstring.

    Parameters
    ----------
    params : FMU parameters with m, friction.F_s, F_c, V_s, delta, sigma2 (the maps too,
        unless ``force_constant``/``cogging`` are given).
    window : Savitzky-Golay window [samples].
    v_min : the fit uses the longest stretch moving one way faster than this [m/s] (it must
        hold at least half the samples: standstill before and after is cut, not reversals).
    x_skip : travel from the start of that stretch [m] left out (pre-rolling until every
        element slips; 2 Delta_N ~ 0.23 mm for Table 3).
    z : interval half-width in standard errors.
    current_timing : see :func:`feeddrive.identify.mass.fit_mass`.
    """
    Kf = force_constant if force_constant is not None else params
    Fcg = cogging if cogging is not None else params
    x = np.asarray(x, dtype=float)
    F_f, v, K, Ts = eq1_friction(time, x, i, params["m"], Kf, Fcg, F_load, window, current_timing)
    G = F_f - params["friction.sigma2"] * apply_kernel(v, K)
    seg, use = _one_way_stretch(x, v, np.isfinite(G), v_min, x_skip)
    s = _level(v, params)
    C_ee, kap_ee = _equation_error(G[seg], s[seg], use[seg], Ts)
    s_seg, G_seg = s[seg], G[seg]
    mask = use[seg] & np.isfinite(apply_kernel(np.zeros_like(s_seg), K))
    best = _output_error(s_seg, G_seg, mask, K, Ts)
    kappa = float(best.x[0])
    # residuals are filtered noise: correct the naive standard error by the kernel's
    # correlation length 1 / sum(K^2)
    se_k = float(jacobian_stderr(best.jac, best.fun)[0] / np.sqrt(np.sum(K**2)))
    C, C_lower, C_upper, C_res, resolved, msg = _interval(kappa, se_k, z)
    Gsim = simulate_lag(s_seg, kappa, best.x[1], Ts)
    return AttractionFit(
        parameters={"friction.C": float(C if resolved else C_lower)},
        stderr={"friction.C": float(se_k / kappa**2) if kappa > 0 else np.inf, "kappa": se_k},
        resolved=bool(resolved),
        C=float(C),
        C_interval=(float(C_lower), float(C_upper)),
        C_lower=float(C_lower),
        C_resolvable_max=float(C_res),
        C_equation_error=C_ee,
        C_equation_error_kappa=1.0 / kap_ee if kap_ee > 0 else np.inf,
        message=msg,
        rms_residual=float(np.sqrt(np.mean(best.fun**2))),
        n_used=int(mask.sum()),
        lag_rms=float(np.sqrt(np.mean((Gsim - s_seg)[mask] ** 2))) if resolved else 0.0,
    )


def _one_way_stretch(
    x: np.ndarray, v: np.ndarray, ok: np.ndarray, v_min: float, x_skip: float
) -> tuple[slice, np.ndarray]:
    """The longest stretch moving one way faster than v_min (standstill before and after is
    cut; it must hold half the valid samples) and the samples of it used (beyond x_skip)."""
    direction = np.sign(np.median(v[ok]))
    moving = ok & (v * direction >= v_min)
    edges = np.flatnonzero(np.diff(np.concatenate(([0], moving.astype(int), [0]))))
    starts, stops = edges[0::2], edges[1::2]
    if len(starts) == 0:
        raise ValueError(f"attraction: no sample moves faster than v_min = {v_min:g} m/s")
    j = int(np.argmax(stops - starts))
    seg = slice(int(starts[j]), int(stops[j]))
    if (stops[j] - starts[j]) < 0.5 * ok.sum():
        raise ValueError(
            "attraction: the velocity reverses or stops inside the run (the longest "
            f"stretch faster than v_min = {v_min:g} m/s is {stops[j] - starts[j]} of "
            f"{int(ok.sum())} samples); Eq. 14 needs a run that never reverses"
        )
    use = np.zeros_like(ok)
    use[seg] = np.abs(x[seg] - x[seg.start]) >= x_skip
    if use.sum() < 50:
        raise ValueError(f"attraction: only {int(use.sum())} usable samples")
    return seg, use


def _equation_error(
    G: np.ndarray, s: np.ndarray, use: np.ndarray, Ts: float
) -> tuple[float, float]:
    """The paper's equation error dG/dt = C r, r = 1 - G/s: C and the inverse fit's kappa."""
    dG = np.gradient(G, Ts)
    r = 1.0 - G / s
    u = use & np.isfinite(dG)
    return float(r[u] @ dG[u] / (r[u] @ r[u])), float(r[u] @ dG[u] / (dG[u] @ dG[u]))


def _output_error(s_seg: np.ndarray, G_seg: np.ndarray, mask: np.ndarray, K: np.ndarray, Ts: float):
    """Output-error fit of (kappa, G0) on the contiguous segment, the simulated G filtered like
    the data: a profile scan over kappa, a bounded refinement, a final joint least squares."""
    rows = np.flatnonzero(mask)

    def profile(kappa: float) -> tuple[float, float]:
        """Cost and best initial value G0 for one kappa (G_sim is affine in G0)."""
        Gp = apply_kernel(simulate_lag(s_seg, kappa, 0.0, Ts), K)[rows]
        H = np.zeros(len(s_seg))
        H[0] = 1.0
        if kappa > 0:
            tau = kappa * 0.5 * (np.abs(s_seg[1:]) + np.abs(s_seg[:-1]))
            H[1:] = np.cumprod(np.exp(-Ts / tau))
        Hf = apply_kernel(H, K)[rows]
        e = G_seg[rows] - Gp
        hh = float(Hf @ Hf)
        G0 = float(Hf @ e / hh) if hh > 1e-12 else float(G_seg[rows[0]])
        r = e - G0 * Hf
        return float(r @ r), G0

    # global scan over kappa (0 and 4 points per decade up to 10 s/N), local refinement
    grid = np.concatenate(([0.0], np.geomspace(1e-8, 10.0, 37)))
    costs = [profile(k)[0] for k in grid]
    j = int(np.argmin(costs))
    if j > 0:
        lo_g, hi_g = np.log(grid[max(j - 1, 1)]), np.log(grid[min(j + 1, len(grid) - 1)])
        ref = minimize_scalar(
            lambda lk: profile(float(np.exp(lk)))[0],
            bounds=(lo_g, hi_g),
            method="bounded",
            options={"xatol": 1e-3},
        )
        k_best = float(np.exp(ref.x)) if ref.fun < costs[j] else float(grid[j])
    else:
        k_best = 0.0

    def resid(th):
        Gs = apply_kernel(simulate_lag(s_seg, th[0], th[1], Ts), K)
        return (Gs - G_seg)[mask]

    return least_squares(
        resid,
        [k_best, profile(k_best)[1]],
        bounds=([0.0, -np.inf], [10.0, np.inf]),
        x_scale=[max(k_best, 1e-6), 1.0],
        max_nfev=20,
    )


def _interval(kappa: float, se_k: float, z: float) -> tuple[float, float, float, float, bool, str]:
    """C, its interval from kappa +- z se, the largest resolvable C, whether C is resolved
    (kappa - z se > 0), and the message saying so."""
    C = 1.0 / kappa if kappa > 0 else np.inf
    lo_k, hi_k = kappa - z * se_k, kappa + z * se_k
    C_lower = 1.0 / hi_k
    C_upper = 1.0 / lo_k if lo_k > 0 else np.inf
    resolved = lo_k > 0
    C_res = 1.0 / (z * se_k) if se_k > 0 else np.inf
    if resolved:
        msg = f"C = {C:.4g} N/s (interval {C_lower:.3g} .. {C_upper:.3g} N/s)"
    else:
        msg = (
            f"C >= {C_lower:.3g} N/s: frictional lag below resolution "
            f"(this run resolves C up to ~{C_res:.3g} N/s)"
        )
    return C, C_lower, C_upper, C_res, bool(resolved), msg


def identify_attraction(
    run: Run, params: Mapping[str, float], dc_gain: float | None = None, **kw
) -> AttractionFit:
    """:func:`fit_attraction` on a run (time, x, i; F_load when present).

    ``dc_gain``: for a run without a current column, i = dc_gain * u (the recording format).
    """
    F = run.F_load if run.F_load is not None else 0.0
    try:
        return fit_attraction(
            run.time, signal(run, "x"), current(run, dc_gain), params, F_load=F, **kw
        )
    except ValueError as e:
        raise ValueError(f"{run_label(run)}: {e}") from None
