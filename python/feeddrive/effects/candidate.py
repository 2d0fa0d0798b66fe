"""An effect as a diagnosis candidate (``feeddrive diagnose``): :class:`Variant`, the services
the diagnosis hands a candidate builder (:class:`CandidateContext`), and the effect-agnostic
regressor helpers the builders share.

Each effect module defines ``candidate(ctx) -> list[Variant]`` (its :class:`Effect`'s
``candidate.builder`` names it).  A candidate says how the force residual r would change if
the effect were added to the model (or its value corrected): ``r_new = r - (Phi theta -
base)``, with ``Phi`` the filtered regressors (force units), ``theta`` linear parameters and
``base`` the filtered contribution of the model's current version of the effect (0 when the
effect is off).  Non-linear parameters (Stribeck velocity and exponent, attraction C, extra
wavelengths) are handled as *variants*: a grid searched in sample, the best point refined
(Nelder-Mead / bounded scalar search), and the refined and best grid designs each scored on
held-out data by the diagnosis.  The variant's identifier turns theta into a new model file
(``to_model``).

The builders sit below the diagnosis: what they need of the packages above (the compiled
plant, the GMS, the stacked residual, fits, the residual's spectrum) the diagnosis context
offers through :class:`CandidateContext` (``feeddrive.diagnose.context.Context``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import minimize_scalar

#: Stride of the samples used by hyper-parameter searches (filtered signals are smooth).
SEARCH_STRIDE = 4


@dataclass
class Variant:
    """One design of a candidate: filtered regressors, base, constraints and the identifier."""

    effect: str
    label: str
    Phi: np.ndarray  #: (N, p) filtered regressors
    names: list[str]  #: what each theta is
    #: theta -> the model file with the effect added or corrected (``ModelFile``)
    to_model: Callable[[np.ndarray], Any]
    base: np.ndarray | None = None  #: filtered current contribution (N,) or None
    nonneg: bool = False
    sum_to_one: bool = False
    refine: bool = False  #: the effect is on; this corrects its values
    #: the last ``nuisance`` columns are fitted but identify nothing (``to_model`` ignores
    #: their coefficients) and do not count as parameters
    nuisance: int = 0

    @property
    def n_params(self) -> int:
        return int(self.Phi.shape[1]) - self.nuisance


class ModelView(Protocol):
    """The model a candidate starts from (``feeddrive.model_file.ModelFile``)."""

    @property
    def effects(self) -> Mapping[str, bool]: ...

    @property
    def parameters(self) -> Mapping[str, Any]: ...

    def with_effect(self, effect: str, on: bool = True, **params: Any) -> Any: ...


class ProfileView(Protocol):
    """A friction profile p(x) over knots (``feeddrive.physics.FrictionProfile``)."""

    @property
    def x_start(self) -> float: ...

    @property
    def x_end(self) -> float: ...

    @property
    def c(self) -> tuple[float, ...]: ...

    @property
    def n(self) -> int: ...

    def __call__(self, x: ArrayLike) -> np.ndarray: ...

    def parameters(self) -> dict[str, float | int]: ...


class CandidateContext(Protocol):
    """What the diagnosis hands a candidate builder.

    ``res``: the runs' force residuals (``feeddrive.residual.RunResidual``: ``x``, ``v_f``,
    ``a``, ``i``, ``u``, ``r``, ``F_f``, ``stuck``, ``Ts``, ``start`` ...); ``plant``: the model
    compiled (``feeddrive.physics.PlantParameters``); ``r``: the residual stacked over the
    valid samples.
    """

    @property
    def model(self) -> ModelView: ...

    @property
    def plant(self) -> Any: ...

    @property
    def res(self) -> Sequence[Any]: ...

    @property
    def r(self) -> np.ndarray: ...

    @property
    def n_elements_max(self) -> int:
        """Most Maxwell-slip elements of the FMU."""
        ...

    @property
    def n_harmonics(self) -> int:
        """Harmonic slots of each position map of the FMU."""
        ...

    def stack(
        self, fn: Callable[[Any], Any], filtered: bool = True, mask_stuck: bool = False
    ) -> np.ndarray:
        """Columns ``fn(run)`` of every run, filtered like the residual, stacked."""
        ...

    def unstack(self, vec: np.ndarray) -> list[np.ndarray]:
        """A stacked vector back to per-run arrays."""
        ...

    def all(self, name: str) -> np.ndarray:
        """A per-sample attribute of the residuals stacked."""
        ...

    def sliding_fraction(self, q: Any) -> np.ndarray:
        """Share of the friction that slides along run ``q``."""
        ...

    def sliding_level(self, q: Any) -> np.ndarray:
        """sgn(v) S(|v|) times the sliding share along run ``q`` [N]."""
        ...

    def gms_start(self, q: Any, n: int) -> np.ndarray | None:
        """Run ``q``'s estimated GMS start forces for ``n`` elements, or None."""
        ...

    def gms_force(self, q: Any, friction: Any, F0: ArrayLike | None) -> np.ndarray:
        """GMS friction (``friction``: ``GMSParameters``) along run ``q`` [N]."""
        ...

    def stribeck_drop(self, v: ArrayLike, V_s: float, delta: float) -> np.ndarray:
        """The Stribeck drop's shape (Eq. 12), 1 at rest."""
        ...

    def profile_basis(self, x: ArrayLike, x_start: float, x_end: float, n: int) -> np.ndarray:
        """The basis B_j(x) of a friction profile over ``n`` knots."""
        ...

    def friction_profile(
        self, x_start: float, x_end: float, c: np.ndarray | Sequence[float]
    ) -> ProfileView:
        """The friction profile with knot values ``c``."""
        ...

    def model_profile(self) -> ProfileView:
        """The model's friction profile."""
        ...

    def held_current(self, i: ArrayLike) -> np.ndarray:
        """The current as the plant holds it over a sample."""
        ...

    def load_acceleration(self, a: ArrayLike, Ts: float, f: float, zeta: float) -> np.ndarray:
        """The acceleration response of a load on a spring to the slide's ``a``."""
        ...

    def load_free_response(self, a: ArrayLike, Ts: float, f: float, zeta: float) -> np.ndarray:
        """The load's free responses from the first valid sample (two columns)."""
        ...

    def fit_compliance(
        self, y_runs: list[np.ndarray], stride: int, nuisance: list[np.ndarray | None]
    ) -> tuple[float, float]:
        """(f [Hz], zeta) of a load on a spring fitted to the per-run residuals ``y_runs``."""
        ...

    def spatial_spectrum(self, weight: str | None) -> tuple[np.ndarray, np.ndarray]:
        """(wavelengths, amplitudes) of the residual over position."""
        ...

    def spectral_peaks(
        self, lams: np.ndarray, amps: np.ndarray, exclude: Sequence[float], n_peaks: int
    ) -> list[tuple[float, float]]:
        """The strongest peaks of a spectrum away from ``exclude``."""
        ...


#: A candidate builder: the effect's variants from a diagnosis context.
Builder = Callable[[CandidateContext], list[Variant]]


def poly_basis(x: np.ndarray, centre: float, half: float, powers: range) -> np.ndarray:
    """Columns ((x - centre)/half)^k for k in ``powers``."""
    xi = (x - centre) / half
    return np.column_stack([xi**k for k in powers])


def poly_to_x(
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


def span(ctx: CandidateContext) -> tuple[float, float]:
    """Centre and half-width [m] of the stroke the runs visited (at least 1 mm)."""
    x = ctx.all("x")
    lo, hi = float(x.min()), float(x.max())
    return 0.5 * (lo + hi), max(0.5 * (hi - lo), 1e-3)


def explained(A: np.ndarray, y: np.ndarray) -> float:
    """Sum of squares of y explained by the columns of A (normal equations), on every
    ``SEARCH_STRIDE``-th sample."""
    A = np.ascontiguousarray(A.reshape(len(y), -1)[::SEARCH_STRIDE])
    y = y[::SEARCH_STRIDE]
    G = A.T @ A
    c = A.T @ y
    th = np.linalg.lstsq(G, c, rcond=None)[0]
    return float(c @ th)


Weight = Callable[[Any], np.ndarray]


def _fourier(ctx: CandidateContext, w: Weight, wl: list[float]) -> np.ndarray:
    def cols(q: Any) -> np.ndarray:
        th = 2 * np.pi * q.x[:, None] / np.asarray(wl)[None, :]
        ww = w(q)[:, None]
        return np.column_stack([ww * np.cos(th), ww * np.sin(th)])

    return ctx.stack(cols, mask_stuck=True)


def _refine_wavelengths(
    ctx: CandidateContext, w: Weight, fixed: list[float], extra: list[float]
) -> list[tuple[float, float]]:
    """Extra wavelengths refined one at a time (bounded scalar search within +-8 %) by the
    least-squares fit of all harmonics together (existing ones included)."""
    out: list[float] = []
    for lam0 in extra:

        def sse(lam: float) -> float:
            A = _fourier(ctx, w, fixed + out + [lam])
            return -explained(A, ctx.r)

        best = minimize_scalar(
            sse,
            bounds=(0.92 * lam0, 1.08 * lam0),
            method="bounded",
            options={"xatol": 5e-4 * lam0, "maxiter": 14},
        )
        out.append(float(best.x))
    return [(lam, 0.0) for lam in out]


def periodic_variants(
    ctx: CandidateContext, name: str, effect: str, weighted: bool
) -> list[Variant]:
    """The variants of the Fourier part of a position map ``name`` (``cogging.*`` or
    ``ripple.*`` parameters) for effect ``effect``: its used harmonics corrected, and with up
    to two extra wavelengths from the residual's spatial spectrum (refined).  ``weighted``: the
    map scales the current (a force constant): columns times i, none without a current."""
    m = ctx.model
    p = m.parameters
    on = m.effects[effect]
    if weighted and any(q.i is None for q in ctx.res):
        return []
    used = [
        j
        for j in range(1, ctx.n_harmonics + 1)
        if float(p[f"{name}.a[{j}]"]) != 0.0 or float(p[f"{name}.b[{j}]"]) != 0.0
    ]
    free = [j for j in range(1, ctx.n_harmonics + 1) if j not in used]
    lams_used = [float(p[f"{name}.lambda[{j}]"]) for j in used]
    lams, amps = ctx.spatial_spectrum("i" if weighted else None)
    peaks = ctx.spectral_peaks(lams, amps, lams_used, min(2, len(free)))

    def w(q: Any) -> np.ndarray:
        return q.i if weighted else np.ones(len(q.r))

    peaks = _refine_wavelengths(ctx, w, lams_used, [lam for lam, _ in peaks])
    out = []
    for n_extra in range(len(peaks) + 1):
        extra = [lam for lam, _ in peaks[:n_extra]]
        slots = used + free[:n_extra]
        wl = lams_used + extra
        if not slots:
            continue

        def cols(q: Any, wl: list[float] = wl) -> np.ndarray:
            th = 2 * np.pi * q.x[:, None] / np.asarray(wl)[None, :]
            ww = w(q)[:, None]
            return np.column_stack([ww * np.cos(th), ww * np.sin(th)])

        sign = -1.0 if weighted else 1.0  # more K_f is more motor force: r = -(dK_f) i
        Phi = sign * ctx.stack(cols, mask_stuck=True)

        def to_model(th: np.ndarray, slots: list[int] = slots, wl: list[float] = wl) -> Any:
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


def one_column(
    ctx: CandidateContext,
    effect: str,
    label: str,
    parameter: str,
    column: Callable[[Any], np.ndarray],
    filtered: bool = True,
    mask_stuck: bool = False,
) -> list[Variant]:
    """The variant of an effect one column ``column(run)`` adds: its coefficient corrects
    ``parameter`` (from 0 when the effect is off; the model's value when on)."""
    m = ctx.model
    on = m.effects[effect]
    old = float(m.parameters[parameter]) if on else 0.0
    Phi = ctx.stack(column, filtered=filtered, mask_stuck=mask_stuck)
    return [
        Variant(
            effect,
            label,
            Phi,
            [parameter],
            refine=on,
            to_model=lambda th: m.with_effect(effect, True, **{parameter: old + th[0]}),
        )
    ]


def polynomial_variant(
    ctx: CandidateContext,
    effect: str,
    prefix: str,
    old: np.ndarray,
    stroke: tuple[float, float],
    Phi: np.ndarray,
    label: str,
    names: list[str],
) -> Variant:
    """The variant of a polynomial map ``prefix.c[0..]`` over the stroke (centre,
    half-width): theta, the coefficients in the normalised position, added to ``old``."""
    m = ctx.model
    order = len(old) - 1
    powers = range(order + 1)
    c, h = stroke

    def to_model(th: np.ndarray) -> Any:
        new = old + poly_to_x(th, powers, c, h, order)
        return m.with_effect(
            effect, True, **{f"{prefix}.c[{k}]": float(new[k]) for k in range(order + 1)}
        )

    return Variant(effect, label, Phi, names, refine=m.effects[effect], to_model=to_model)
