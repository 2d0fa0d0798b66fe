"""One regressor design (scorer) and identifier per effect of the catalogue (docs/effects.md).

Each candidate says how the force residual r would change if the effect were added to the
model (or its value corrected): ``r_new = r - (Phi theta - base)``, with ``Phi`` the
filtered regressors (force units), ``theta`` linear parameters and ``base`` the filtered
contribution of the model's current version of the effect (0 when the effect is off).
Non-linear parameters (Stribeck velocity and exponent, attraction C, extra wavelengths)
are handled as *variants*: a grid searched in sample, the best point refined (Nelder-Mead /
bounded scalar search), and the refined and best grid designs each scored on held-out data
by the workflow.  The frictional-lag scale and the linear Stribeck drop are fitted; C,
V_s, delta and the wavelengths are the variant's.

The identifier turns (variant, theta) into a new model file (``to_model``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import minimize, minimize_scalar

from ..effects import EFFECTS, Effect
from ..fits.compliance import fit_compliance
from ..model_file import ModelFile
from ..paper import N_ELEMENTS_MAX, N_HARMONICS
from ..physics import (
    FrictionProfile,
    gms_force,
    held_current,
    load_acceleration,
    load_free_response,
    profile_basis,
    stribeck_drop,
)
from ..residual import RunResidual
from .context import Context
from .localise import spatial_spectrum, spectral_peaks

#: Maxwell-slip element travels tried by the pre-rolling candidate [m].
PREROLL_DELTAS = tuple(np.geomspace(2e-6, 300e-6, 8).tolist())
#: Stribeck velocity [m/s] and exponent grid.
STRIBECK_VS = tuple(np.geomspace(3e-4, 3e-2, 11).tolist())
STRIBECK_DELTA = (0.4, 0.6, 1.0, 1.5, 2.0)
#: Stribeck grid points (best in-sample) kept as variants beside the refined one.
STRIBECK_KEEP = 3
#: Attraction parameter grid [N/s] (the best point is refined between its neighbours).
LAG_C = tuple(np.geomspace(3.0, 3e5, 11).tolist())
#: Knot counts of the position_friction candidate over the stroke the runs visited (the
#: FMU holds up to 16); each is a variant, the parsimony rule prefers fewer knots.
PROFILE_KNOTS = (4, 7, 10, 13, 16)


@dataclass
class Variant:
    """One design of a candidate: filtered regressors, base, constraints and the identifier."""

    effect: str
    label: str
    Phi: np.ndarray  #: (N, p) filtered regressors
    names: list[str]  #: what each theta is
    to_model: Callable[[np.ndarray], ModelFile]
    base: np.ndarray | None = None  #: filtered current contribution (N,) or None
    nonneg: bool = False
    sum_to_one: bool = False
    refine: bool = False  #: the effect is on; this corrects its values
    #: the last ``nuisance`` columns are fitted but identify nothing (``to_model`` ignores
    #: their coefficients) and do not count as parameters
    nuisance: int = 0

    @property
    def n_params(self) -> int:
        return self.Phi.shape[1] - self.nuisance


def _current(q: RunResidual) -> np.ndarray:
    """The run's current (a candidate that reads it is offered only when every run has one)."""
    if q.i is None:
        raise ValueError(f"{q.name}: no current")
    return q.i


def _poly_basis(x: np.ndarray, centre: float, half: float, powers: range) -> np.ndarray:
    xi = (x - centre) / half
    return np.column_stack([xi**k for k in powers])


def _poly_to_x(
    theta_xi: np.ndarray, powers: range, centre: float, half: float, order: int
) -> np.ndarray:
    """Coefficients in x (powers 0..order) of sum theta_k ((x - centre)/half)^k."""
    full = np.zeros(order + 1)
    for k, t in zip(powers, theta_xi, strict=True):
        full[k] = t
    P = np.polynomial.Polynomial(full, domain=[centre - half, centre + half])
    c = P.convert().coef
    out = np.zeros(order + 1)
    out[: len(c)] = c[: order + 1]
    return out


def _span(ctx: Context) -> tuple[float, float]:
    x = ctx.all("x")
    lo, hi = float(x.min()), float(x.max())
    return 0.5 * (lo + hi), max(0.5 * (hi - lo), 1e-3)


# --------------------------------------------------------------------------- simple forces
def offset_force(ctx: Context) -> list[Variant]:
    m = ctx.model
    on = m.effects["offset_force"]
    old = float(m.parameters["offset.F"]) if on else 0.0
    Phi = ctx.stack(lambda q: np.ones(len(q.r)), mask_stuck=True)
    return [
        Variant(
            "offset_force",
            "constant",
            Phi,
            ["offset.F"],
            refine=on,
            to_model=lambda th: m.with_effect("offset_force", True, **{"offset.F": old + th[0]}),
        )
    ]


def mass(ctx: Context) -> list[Variant]:
    m = ctx.model
    old = float(m.parameters["m"])
    Phi = ctx.stack(lambda q: q.a, filtered=False)
    return [
        Variant(
            "mass",
            "acceleration",
            Phi,
            ["m"],
            refine=True,
            to_model=lambda th: m.with_effect("mass", True, m=old + th[0]),
        )
    ]


def viscous(ctx: Context) -> list[Variant]:
    m = ctx.model
    on = m.effects["viscous"]
    old = float(m.parameters["friction.sigma2"]) if on else 0.0
    Phi = ctx.stack(lambda q: q.v_f, mask_stuck=True)
    return [
        Variant(
            "viscous",
            "v",
            Phi,
            ["friction.sigma2"],
            refine=on,
            to_model=lambda th: m.with_effect("viscous", True, **{"friction.sigma2": old + th[0]}),
        )
    ]


def asymmetric_friction(ctx: Context) -> list[Variant]:
    m = ctx.model
    on = m.effects["asymmetric_friction"]
    dF = float(m.parameters["asymmetry.dF"]) if on else 0.0
    ds = float(m.parameters["asymmetry.dsigma2"]) if on else 0.0
    # the level shift acts through the sliding elements only (stuck ones ignore it)
    frac = iter([_sliding_fraction(ctx, q) for q in ctx.res])
    Phi = ctx.stack(
        lambda q: np.column_stack([-(q.v_f < 0).astype(float) * next(frac), q.v_f * (q.v_f < 0)]),
        mask_stuck=True,
    )
    return [
        Variant(
            "asymmetric_friction",
            "indicator(v<0), v*(v<0)",
            Phi,
            ["asymmetry.dF", "asymmetry.dsigma2"],
            refine=on,
            to_model=lambda th: m.with_effect(
                "asymmetric_friction",
                True,
                **{"asymmetry.dF": dF + th[0], "asymmetry.dsigma2": ds + th[1]},
            ),
        )
    ]


# --------------------------------------------------------------------------- friction curve
def _sliding_fraction(ctx: Context, q) -> np.ndarray:
    """Share of the friction that slides (sum of nu_i of slipping GMS elements); static
    model: 1 except on stuck samples.  Memoised per context and run."""
    key = ("sliding", id(q))
    if key not in ctx.cache:
        ctx.cache[key] = _sliding(ctx, q)
    return ctx.cache[key]


def _sliding(ctx: Context, q) -> np.ndarray:
    if not ctx.plant.prerolling:
        return (~q.stuck).astype(float)
    prm = ctx.plant.friction
    _, Fe = gms_force(q.x, q.v_f, q.Ts, prm, F0=_start(q, len(prm.nu)), return_elements=True)
    lim = np.outer(prm.level(q.v_f, q.x), np.asarray(prm.nu))
    slipping = np.abs(Fe) >= 0.98 * lim
    return (slipping * np.asarray(prm.nu)).sum(axis=1) / max(sum(prm.nu), 1e-12)


def _sliding_level(ctx: Context, q) -> np.ndarray:
    """The friction the profile p(x) scales along a run [N]: sgn(v) S(|v|) (the level without
    the model's own profile) times the sliding share; memoised per context and run."""
    key = ("sliding_level", id(q))
    if key not in ctx.cache:
        ctx.cache[key] = (
            np.sign(q.v_f) * ctx.plant.friction.level(q.v_f) * _sliding_fraction(ctx, q)
        )
    return ctx.cache[key]


def position_friction(ctx: Context) -> list[Variant]:
    """p(x) = 1 + sum_j c_j B_j(x) (``position_friction``): regressors B_j(x) times the sliding
    friction, filtered like the residual, uniform knots over the stroke the runs visited, one
    variant per count of ``PROFILE_KNOTS``.  With the effect on (a refinement) the model's own
    knots are corrected (c + dc), and each grid of the visited stroke is offered too, fitted
    in place of the model's profile (its contribution is the variant's ``base``): the polish
    after a first step can so move to finer knots than the held-out choice."""
    m = ctx.model
    on = m.effects["position_friction"]
    x = ctx.all("x")
    lo, hi = float(x.min()), float(x.max())
    grids: list[tuple[float, float, int, np.ndarray | None]] = []
    base = None
    if on:
        prof = FrictionProfile.from_params(m.parameters)
        grids.append((prof.x_start, prof.x_end, prof.n, np.asarray(prof.c)))
        base = ctx.stack(lambda q: (prof(q.x) - 1.0) * _sliding_level(ctx, q), mask_stuck=True)[
            :, 0
        ]
    if hi - lo >= 1e-3:  # else no stroke to tell a profile from a level
        grids += [(lo, hi, n, None) for n in PROFILE_KNOTS]
    out = []
    for x0, x1, n, old in grids:

        def basis(q: RunResidual, x0: float = x0, x1: float = x1, n: int = n) -> np.ndarray:
            return profile_basis(q.x, x0, x1, n) * _sliding_level(ctx, q)[:, None]

        Phi = ctx.stack(basis, mask_stuck=True)

        def to_model(th: np.ndarray, x0=x0, x1=x1, old=old) -> ModelFile:
            c = (old if old is not None else 0.0) + np.asarray(th, dtype=float)
            prof = FrictionProfile(float(x0), float(x1), tuple(float(v) for v in c))
            return m.with_effect("position_friction", True, **prof.parameters())

        label = f"{n} knots over {x0 * 1e3:.1f}-{x1 * 1e3:.1f} mm"
        out.append(
            Variant(
                "position_friction",
                label + (" (new grid)" if on and old is None else ""),
                Phi,
                [f"c[{j + 1}]" for j in range(n)],
                refine=on,
                base=base if on and old is None else None,
                to_model=to_model,
            )
        )
    return out


def stribeck(ctx: Context) -> list[Variant]:
    m = ctx.model
    p = m.parameters
    on = m.effects["stribeck"]
    frac = [_sliding_fraction(ctx, q) for q in ctx.res]
    F_c = float(p["friction.F_c"])
    base = None
    if on:
        Vs0, d0, dS0 = (
            float(p["friction.V_s"]),
            float(p["friction.delta"]),
            float(p["friction.F_s"]) - F_c,
        )
        it = iter(frac)
        base = ctx.stack(lambda q: next(it) * dS0 * stribeck_drop(q.v_f, Vs0, d0))[:, 0]
    y = ctx.r + (base if base is not None else 0.0)

    def column(Vs: float, d: float) -> np.ndarray:
        it = iter(frac)
        return ctx.stack(lambda q: next(it) * stribeck_drop(q.v_f, Vs, d))

    # grid by in-sample explained energy (one column each), then a local refinement of the
    # best (log V_s, delta); the few best are scored on held-out blocks by the workflow
    grid = sorted(
        ((Vs, d) for Vs in STRIBECK_VS for d in STRIBECK_DELTA),
        key=lambda p: -_explained(column(*p), y),
    )[:STRIBECK_KEEP]

    def neg(z):
        return -_explained(column(float(np.exp(z[0])), float(np.clip(z[1], 0.2, 3.0))), y)

    opt = minimize(
        neg,
        [np.log(grid[0][0]), grid[0][1]],
        method="Nelder-Mead",
        options={"xatol": 0.02, "fatol": 1e-6 * float(y @ y), "maxiter": 60},
    )
    refined = (float(np.exp(opt.x[0])), float(np.clip(opt.x[1], 0.2, 3.0)))
    out = []
    for Vs, d in [refined] + grid:

        def to_model(th: np.ndarray, Vs: float = Vs, d: float = d) -> ModelFile:
            return m.with_effect(
                "stribeck",
                True,
                **{"friction.F_s": F_c + th[0], "friction.V_s": Vs, "friction.delta": d},
            )

        out.append(
            Variant(
                "stribeck",
                f"V_s={Vs * 1e3:.3g} mm/s, delta={d:.3g}",
                column(Vs, d),
                ["F_s - F_c"],
                base=base,
                refine=on,
                nonneg=True,
                to_model=to_model,
            )
        )
    return out


def _start(q, n: int) -> np.ndarray | None:
    """The run's estimated GMS start forces (:mod:`feeddrive.physics.gms_start`) when the
    residual's model has ``n`` elements, else None (virgin)."""
    F0 = None if q.start is None else q.start.F0
    return F0 if F0 is not None and len(F0) == n else None


def _gms_unit_columns(ctx: Context, q, deltas) -> np.ndarray:
    """Friction of one Maxwell-slip element (nu = 1, travel Delta) per Delta, no viscous;
    each starts holding the friction the residual's model held at the first sample (the
    run's estimated start, clipped to the element's level), virgin without one."""
    prm = ctx.plant.friction
    held = float(np.sum(q.start.F0)) if q.start is not None else 0.0
    cols = []
    for D in deltas:
        pe = replace(prm, nu=(1.0,), k=(prm.F_s / D,), sigma2=0.0, dsigma2=0.0)
        F0 = [float(np.clip(held, -(prm.F_s + prm.dF), prm.F_s))]
        cols.append(gms_force(q.x, q.v_f, q.Ts, pe, F0=F0))
    return np.column_stack(cols)


def prerolling(ctx: Context) -> list[Variant]:
    m = ctx.model
    on = m.effects["prerolling"]
    prm = ctx.plant.friction
    deltas = PREROLL_DELTAS
    Phi = ctx.stack(lambda q: _gms_unit_columns(ctx, q, deltas))
    base = ctx.stack(lambda q: q.F_f - prm.viscous(q.v_f))[:, 0]
    F_s = prm.F_s

    def to_model(th: np.ndarray) -> ModelFile:
        th = np.clip(th, 0.0, None)
        keep = np.flatnonzero(th > 1e-3 * th.max())[:N_ELEMENTS_MAX]
        nu = th[keep] / th[keep].sum()
        kk = nu * F_s / np.asarray(deltas)[keep]
        upd: dict = {"friction.N": int(len(keep))}
        for j in range(N_ELEMENTS_MAX):
            upd[f"friction.nu[{j + 1}]"] = float(nu[j]) if j < len(keep) else 0.0
            upd[f"friction.k[{j + 1}]"] = float(kk[j]) if j < len(keep) else 1.0e5
        return m.with_effect("prerolling", True, **upd)

    return [
        Variant(
            "prerolling",
            f"Maxwell-slip, {len(deltas)} elements, "
            f"Delta {deltas[0] * 1e6:.3g}..{deltas[-1] * 1e6:.3g} um",
            Phi,
            [f"W/F_s at Delta={D * 1e6:.3g} um" for D in deltas],
            base=base,
            nonneg=True,
            sum_to_one=True,
            refine=on,
            to_model=to_model,
        )
    ]


def frictional_lag(ctx: Context) -> list[Variant]:
    m = ctx.model
    if not m.effects["prerolling"]:
        return []  # slip-phase attraction only exists in the GMS
    on = m.effects["frictional_lag"]
    prm = ctx.plant.friction
    base = ctx.stack(lambda q: q.F_f - prm.viscous(q.v_f))[:, 0]
    y = ctx.r + base
    C_now = float(m.parameters["friction.C"]) if on else np.inf

    def column(C: float) -> np.ndarray:
        pc = replace(prm, C=C)
        return ctx.stack(
            lambda q: gms_force(q.x, q.v_f, q.Ts, pc, F0=_start(q, len(pc.nu))) - pc.viscous(q.v_f)
        )

    cols = {C: column(C) for C in LAG_C if not (on and abs(np.log(C / C_now)) < 0.2)}
    if not cols:
        return []
    expl = {C: _explained(A, y) for C, A in cols.items()}
    Cb = max(expl, key=lambda C: expl[C])
    # refine log C between the neighbours of the best grid point
    k = LAG_C.index(Cb)
    lo, hi = np.log(LAG_C[max(k - 1, 0)]), np.log(LAG_C[min(k + 1, len(LAG_C) - 1)])
    if hi > lo:
        opt = minimize_scalar(
            lambda z: -_explained(column(float(np.exp(z))), y),
            bounds=(lo, hi),
            method="bounded",
            options={"xatol": 0.05, "maxiter": 8},
        )
        Cr = float(np.exp(opt.x))
        if -opt.fun > expl[Cb]:
            cols = {Cr: column(Cr), **cols}
    out = []
    for C, Phi in cols.items():

        def to_model(th: np.ndarray, C: float = C) -> ModelFile:
            return m.with_effect("frictional_lag", True, **{"friction.C": C})

        out.append(
            Variant(
                "frictional_lag",
                f"C={C:.3g} N/s",
                Phi,
                ["scale"],
                base=base,
                refine=on,
                to_model=to_model,
            )
        )
    return out


# --------------------------------------------------------------------------- position maps
def cogging_aperiodic(ctx: Context) -> list[Variant]:
    m = ctx.model
    on = m.effects["cogging_aperiodic"]
    c, h = _span(ctx)
    powers = range(4)
    Phi = ctx.stack(lambda q: _poly_basis(q.x, c, h, powers), mask_stuck=True)
    old = (
        np.array([float(m.parameters[f"cogging.c[{k}]"]) for k in range(4)]) if on else np.zeros(4)
    )

    def to_model(th: np.ndarray) -> ModelFile:
        new = old + _poly_to_x(th, powers, c, h, 3)
        return m.with_effect(
            "cogging_aperiodic", True, **{f"cogging.c[{k}]": float(new[k]) for k in range(4)}
        )

    return [
        Variant(
            "cogging_aperiodic",
            "cubic in x",
            Phi,
            [f"xi^{k}" for k in powers],
            refine=on,
            to_model=to_model,
        )
    ]


def ripple_aperiodic(ctx: Context) -> list[Variant]:
    m = ctx.model
    if any(q.i is None for q in ctx.res):
        return []  # F = gain * u: no K_f(x) to refine
    on = m.effects["ripple_aperiodic"]
    c, h = _span(ctx)
    # the constant is included: with the polynomial off the model's K_f is c0 alone, and the
    # truth's drift over a short stretch of stroke is mostly a change of level (which trades
    # off with the mass only when friction and cogging leave i proportional to a)
    powers = range(3)
    # more K_f means more motor force: r = -(dK_f) i
    Phi = -ctx.stack(
        lambda q: _current(q)[:, None] * _poly_basis(q.x, c, h, powers), mask_stuck=True
    )
    old = np.array([float(m.parameters[f"ripple.c[{k}]"]) for k in range(3)])
    if not on:
        old[1:] = 0.0  # off: K_f = c0 on the stroke

    def to_model(th: np.ndarray) -> ModelFile:
        new = old + _poly_to_x(th, powers, c, h, 2)
        return m.with_effect(
            "ripple_aperiodic", True, **{f"ripple.c[{k}]": float(new[k]) for k in range(3)}
        )

    return [
        Variant(
            "ripple_aperiodic",
            "i * (1, x, x^2)",
            Phi,
            ["i", "i*xi", "i*xi^2"],
            refine=on,
            to_model=to_model,
        )
    ]


def _periodic(ctx: Context, name: str, effect: str) -> list[Variant]:
    m = ctx.model
    p = m.parameters
    on = m.effects[effect]
    weighted = name == "ripple"
    if weighted and any(q.i is None for q in ctx.res):
        return []
    used = [
        j
        for j in range(1, N_HARMONICS + 1)
        if float(p[f"{name}.a[{j}]"]) != 0.0 or float(p[f"{name}.b[{j}]"]) != 0.0
    ]
    free = [j for j in range(1, N_HARMONICS + 1) if j not in used]
    lams_used = [float(p[f"{name}.lambda[{j}]"]) for j in used]
    lams, amps = spatial_spectrum(ctx.res, weight="i" if weighted else None)
    peaks = spectral_peaks(lams, amps, exclude=lams_used, n_peaks=min(2, len(free)))
    w = (lambda q: q.i) if weighted else (lambda q: np.ones(len(q.r)))
    peaks = _refine_wavelengths(ctx, w, lams_used, [lam for lam, _ in peaks])
    out = []
    for n_extra in range(len(peaks) + 1):
        extra = [lam for lam, _ in peaks[:n_extra]]
        slots = used + free[:n_extra]
        wl = lams_used + extra
        if not slots:
            continue

        def cols(q, wl=wl):
            th = 2 * np.pi * q.x[:, None] / np.asarray(wl)[None, :]
            ww = w(q)[:, None]
            return np.column_stack([ww * np.cos(th), ww * np.sin(th)])

        sign = -1.0 if weighted else 1.0  # more K_f is more motor force: r = -(dK_f) i
        Phi = sign * ctx.stack(cols, mask_stuck=True)

        def to_model(th, slots=slots, wl=wl):
            n = len(slots)
            upd = {}
            for k, (j, lam) in enumerate(zip(slots, wl, strict=True)):
                a0 = float(p[f"{name}.a[{j}]"]) if on else 0.0
                b0 = float(p[f"{name}.b[{j}]"]) if on else 0.0
                upd[f"{name}.a[{j}]"] = a0 + float(th[k])
                upd[f"{name}.b[{j}]"] = b0 + float(th[n + k])
                upd[f"{name}.lambda[{j}]"] = float(lam)
            return m.with_effect(effect, True, **upd)

        label = "harmonics at " + ", ".join(f"{lam * 1e3:.4g}" for lam in wl) + " mm"
        if extra:
            label += f" (extra: {', '.join(f'{lam * 1e3:.4g}' for lam in extra)} mm)"
        out.append(
            Variant(
                effect,
                label,
                Phi,
                [f"a@{lam * 1e3:.4g}mm" for lam in wl] + [f"b@{lam * 1e3:.4g}mm" for lam in wl],
                refine=on,
                to_model=to_model,
            )
        )
    return out


#: Stride of the samples used by hyper-parameter searches (filtered signals are smooth).
SEARCH_STRIDE = 4


def _explained(A: np.ndarray, y: np.ndarray) -> float:
    """Sum of squares of y explained by the columns of A (normal equations), on every
    ``SEARCH_STRIDE``-th sample."""
    A = np.ascontiguousarray(A.reshape(len(y), -1)[::SEARCH_STRIDE])
    y = y[::SEARCH_STRIDE]
    G = A.T @ A
    c = A.T @ y
    th = np.linalg.lstsq(G, c, rcond=None)[0]
    return float(c @ th)


def _fourier(ctx: Context, w, wl: list[float]) -> np.ndarray:
    def cols(q):
        th = 2 * np.pi * q.x[:, None] / np.asarray(wl)[None, :]
        ww = w(q)[:, None]
        return np.column_stack([ww * np.cos(th), ww * np.sin(th)])

    return ctx.stack(cols, mask_stuck=True)


def _refine_wavelengths(
    ctx: Context, w, fixed: list[float], extra: list[float]
) -> list[tuple[float, float]]:
    """Extra wavelengths refined one at a time (bounded scalar search within +-8 %) by the
    least-squares fit of all harmonics together (existing ones included)."""
    out: list[float] = []
    for lam0 in extra:

        def sse(lam):
            A = _fourier(ctx, w, fixed + out + [lam])
            return -_explained(A, ctx.r)

        best = minimize_scalar(
            sse,
            bounds=(0.92 * lam0, 1.08 * lam0),
            method="bounded",
            options={"xatol": 5e-4 * lam0, "maxiter": 14},
        )
        out.append(float(best.x))
    return [(lam, 0.0) for lam in out]


def cogging_periodic(ctx: Context) -> list[Variant]:
    return _periodic(ctx, "cogging", "cogging_periodic")


def ripple_periodic(ctx: Context) -> list[Variant]:
    return _periodic(ctx, "ripple", "ripple_periodic")


# --------------------------------------------------------------------------- compliance
def compliance(ctx: Context) -> list[Variant]:
    """A load m2 on a spring-damper: the residual gains m2 H(s) a (the load's inertial force,
    ``feeddrive.physics.compliance``), a = the (already filtered) measured acceleration.
    (f, zeta) by the grid + Nelder-Mead of :func:`feeddrive.fits.compliance.fit_compliance`;
    variants: m2 alone, and m2 with a change of the slide's mass; both carry the load's free
    responses from each run's first valid sample (its state there is unknown) as nuisance
    columns.  The residual's GMS start forces were estimated without the load: the search
    fits them again with it (their sensitivity as free columns), and every column is taken
    orthogonal to them (:meth:`Context.stack`), or the start would keep part of the load's
    first oscillations and bias its damping.  At f -> inf the regressor is the mass's: the
    workflow ranks this family only when held-out data show it beyond the mass
    (workflow.NESTED)."""
    m = ctx.model
    on = m.effects["compliance"]
    P = ctx.plant.compliance
    if P.sensor_side != 0:
        return []  # the residual assumes the encoder on the slide
    base = None
    if on:
        base = ctx.stack(
            lambda q: P.m2 * load_acceleration(q.a, q.Ts, P.f, P.zeta), filtered=False
        )[:, 0]
    y = ctx.r + (base if base is not None else 0.0)
    starts = [
        q.start.full_basis(len(q.r)) if q.start is not None and q.start.basis is not None else None
        for q in ctx.res
    ]
    try:
        fit = fit_compliance(
            [q.a for q in ctx.res],
            ctx.unstack(y),
            [q.Ts for q in ctx.res],
            stride=SEARCH_STRIDE,
            nuisance=starts,
        )
    except ValueError:
        return []  # no acceleration to see a load by
    f, z = fit.f, fit.zeta
    col = ctx.stack(lambda q: load_acceleration(q.a, q.Ts, f, z), filtered=False)
    acc = ctx.stack(lambda q: q.a, filtered=False)
    start = _start_columns(ctx, f, z)
    names = [f"load state at the start of {q.name} ({k})" for q in ctx.res for k in ("1", "2")]
    m_old = float(m.parameters["m"])
    upd = {"compliance.f": f, "compliance.zeta": z}
    label = f"f={f:.4g} Hz, zeta={z:.3g}"
    return [
        Variant(
            "compliance",
            label,
            np.column_stack([col, start]),
            ["compliance.m2"] + names,
            base=base,
            refine=on,
            nuisance=start.shape[1],
            to_model=lambda th: m.with_effect(
                "compliance", True, **{"compliance.m2": float(th[0]), **upd}
            ),
        ),
        Variant(
            "compliance",
            label + ", with a mass change",
            np.column_stack([col, acc, start]),
            ["compliance.m2", "m"] + names,
            base=base,
            refine=on,
            nuisance=start.shape[1],
            to_model=lambda th: m.with_effect(
                "compliance", True, m=m_old + float(th[1]), **{"compliance.m2": float(th[0]), **upd}
            ),
        ),
    ]


def _start_columns(ctx: Context, f: float, zeta: float) -> np.ndarray:
    """Free responses of the load from each run's first valid sample, per run (the load's
    state there is not measured: ``feeddrive.physics.load_free_response``; two columns per
    run, zero in the other runs' rows), stacked orthogonal to the run's GMS start."""
    index = {id(q): j for j, q in enumerate(ctx.res)}

    def cols(q) -> np.ndarray:
        out = np.zeros((len(q.r), 2 * len(ctx.res)))
        j = index[id(q)]
        out[:, 2 * j : 2 * j + 2] = np.nan_to_num(load_free_response(q.a, q.Ts, f, zeta))
        return out

    return ctx.stack(cols, filtered=False)


# --------------------------------------------------------------------------- current loop
def current_dynamics(ctx: Context) -> list[Variant]:
    m = ctx.model
    if m.effects["current_dynamics"]:
        return []
    if not all(
        q.i is not None and q.force_source.startswith("no current measured: i =") for q in ctx.res
    ):
        return []  # measured current, or F = gain * u: the loop is not in the residual
    loop = replace(ctx.plant.current, dynamics=True)

    def col(q):
        return ctx.plant.K_f(q.x) * (held_current(loop.current(q.u)) - q.i)

    Phi = -ctx.stack(col, mask_stuck=True)
    return [
        Variant(
            "current_dynamics",
            "G(z) of the model file instead of G(1)",
            Phi,
            ["scale"],
            to_model=lambda th: m.with_effect("current_dynamics", True),
        )
    ]


def _builder(e: Effect) -> Callable[[Context], list[Variant]]:
    """The candidate family of effect ``e`` (its registry reference names a function here)."""
    module, _, name = e.candidate.builder.partition(":")
    make = globals().get(name) if module == __name__ else None
    if not callable(make):
        raise ImportError(
            f"effect {e.id}: candidate {e.candidate.builder!r} is not a function of {__name__}"
        )
    return make


#: Every candidate family, by catalogue id (the registry's order: feeddrive.effects.EFFECTS).
CANDIDATES: dict[str, Callable[[Context], list[Variant]]] = {e.id: _builder(e) for e in EFFECTS}
