"""Generalized Maxwell-Slip friction (Eqs. 8-12, docs/model.md) driven by a given motion.

C twin: fmu_src/physics/friction_gms.c (the FMU integrates the same hybrid model with events).

    F_f = sum_i F_i + sigma2(v) v
    stuck:    dF_i/dt = k_i v              until sgn(F_i) = sgn(v) and |F_i| >= nu_i S(|v|)
    slipping: dF_i/dt = (C/S)(nu_i s(v) - F_i)   until v crosses zero (then every slipping
              element sticks)

The element forces depend only on the motion, so the model is evaluated along a position and
velocity trajectory (a reference for feedforward).  Between samples the velocity is taken
linear in time; an interval in which v changes sign is split at the crossing (the pieces'
displacements are v0 theta dt / 2 and the remainder of x[k+1] - x[k]).  On each piece the
direction and the Stribeck level S (at the piece's mean speed) are constant, which makes the
update exact: a stuck element moves by k_i dx, and switches to slip where it meets
nu_i S sgn(v) (continuous, the rest of the piece then relaxes toward the same target); a
slipping element relaxes exponentially, F -> t + (F - t) exp(-C tau / S), t = nu_i s(v).
C = inf (``frictional_lag`` off) makes a slipping element follow nu_i s(v) at once.
A piece with no motion (v = 0 at both ends and dx = 0) changes nothing; a reversal of the
direction of motion sticks every slipping element.

Asymmetry (``asymmetric_friction``): for v < 0 the static and Coulomb levels are F_s + dF,
F_c + dF and the viscous coefficient sigma2 + dsigma2.

Position (``position_friction``, :mod:`.friction_position`): the level of either side is
p(x) S(|v|); along a motion each piece takes p at its mid position (the interval's start
plus half the piece's displacement), as gms_track_step of friction_gms.c does.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Literal, overload

import numpy as np
from numpy.typing import ArrayLike

from ..effects import Structure, apply_switches, structure_on
from .friction_curves import FrictionCurve
from .friction_position import FrictionProfile


@dataclass(frozen=True)
class GMSParameters:
    """GMS parameters in SI (effects already applied)."""

    F_s: float
    F_c: float
    V_s: float
    delta: float
    sigma2: float
    C: float
    nu: tuple[float, ...]
    k: tuple[float, ...]
    dF: float = 0.0
    dsigma2: float = 0.0
    #: the level profile p(x) of ``position_friction`` (None: p = 1)
    profile: FrictionProfile | None = None

    def __post_init__(self) -> None:
        if len(self.nu) != len(self.k):
            raise ValueError("friction_gms.py: nu and k must have the same length")
        if self.k and (min(self.k) <= 0 or min(self.nu) < 0):
            raise ValueError("friction_gms.py: need k_i > 0 and nu_i >= 0")
        if not (self.C > 0) or not (self.V_s > 0) or not (self.delta > 0):
            raise ValueError("friction_gms.py: need C > 0 (inf allowed), V_s > 0, delta > 0")

    @classmethod
    def from_params(cls, params: Mapping[str, float], apply_effects: bool = True) -> GMSParameters:
        """From FMU-named parameters (``friction.*``, ``asymmetry.*``); the friction part of
        :func:`feeddrive.physics.params.compile`, which validates them first.

        The elements are those fmu_src/physics/friction_gms.c makes active: i <= friction.N with nu_i > 0.
        With ``apply_effects`` the ``effects.<id>`` switches act once, here, by each effect's
        ``off`` rule (:func:`feeddrive.effects.apply_switches`): ``stribeck`` off sets
        F_s = F_c (the Coulomb level, as the effect catalogue says), ``viscous`` off sets
        sigma2 = dsigma2 = 0, ``frictional_lag`` off sets C = inf, ``asymmetric_friction`` off
        sets dF = dsigma2 = 0; ``position_friction`` on (the plant structure
        :attr:`~feeddrive.effects.Structure.LEVEL_PROFILE`) adds the profile p(x) of
        ``friction_profile.*``.
        """
        try:
            N = int(params["friction.N"])
            nu = [float(params[f"friction.nu[{j}]"]) for j in range(1, N + 1)]
            k = [float(params[f"friction.k[{j}]"]) for j in range(1, N + 1)]
            keep = [j for j in range(N) if nu[j] > 0.0]
            p = cls(
                F_s=float(params["friction.F_s"]),
                F_c=float(params["friction.F_c"]),
                V_s=float(params["friction.V_s"]),
                delta=float(params["friction.delta"]),
                sigma2=float(params["friction.sigma2"]),
                C=float(params["friction.C"]),
                nu=tuple(nu[j] for j in keep),
                k=tuple(k[j] for j in keep),
                dF=float(params.get("asymmetry.dF", 0.0)),
                dsigma2=float(params.get("asymmetry.dsigma2", 0.0)),
                profile=FrictionProfile.from_params(params)
                if structure_on(params, Structure.LEVEL_PROFILE)
                else None,
            )
        except KeyError as e:
            raise KeyError(f"friction_gms.py: parameter {e.args[0]!r} missing") from None
        if not apply_effects:
            return p
        val = apply_switches(params)
        return replace(
            p,
            F_s=float(val["friction.F_s"]),
            sigma2=float(val["friction.sigma2"]),
            C=float(val["friction.C"]),
            dF=float(val.get("asymmetry.dF", 0.0)),
            dsigma2=float(val.get("asymmetry.dsigma2", 0.0)),
        )

    def scale(self, x: ArrayLike | None) -> np.ndarray | float:
        """p(x) of ``position_friction`` [-]; 1 without a profile or without x."""
        if self.profile is None or x is None:
            return 1.0
        return self.profile(x)

    def break_away(self, F: ArrayLike, x: ArrayLike | None = None) -> np.ndarray:
        """The static level F_s of the side of the force F (F < 0: F_s + dF) [N], times p(x)
        (friction_break_away of friction_position.c)."""
        Fs = np.where(np.asarray(F, dtype=float) < 0, self.F_s + self.dF, self.F_s)
        return Fs if self.profile is None or x is None else self.profile(x) * Fs

    @property
    def curve(self) -> FrictionCurve:
        """The steady friction curve of these parameters (both sides)."""
        return FrictionCurve(
            self.F_s, self.F_c, self.V_s, self.delta, self.sigma2, self.dF, self.dsigma2
        )

    def level(self, v: ArrayLike, x: ArrayLike | None = None) -> np.ndarray:
        """S(|v|) of the side of v (v < 0: levels raised by dF) [N]; S(0) = F_s; with a
        profile and x given, p(x) S(|v|) (friction_level_at of friction_position.c)."""
        S = self.curve.level(v)
        return S if self.profile is None or x is None else self.profile(x) * S

    def viscous(self, v: ArrayLike) -> np.ndarray:
        """sigma2 v, with sigma2 + dsigma2 for v < 0 [N]."""
        return self.curve.viscous(v)

    def steady(self, v: ArrayLike, x: ArrayLike | None = None) -> np.ndarray:
        """Steady sliding friction s(v) + sigma2 v (Eq. 12) [N]; 0 at v = 0; the level at x
        (p(x) S) when a profile and x are given."""
        if self.profile is None or x is None:
            return self.curve.steady(v)
        v = np.asarray(v, dtype=float)
        return np.sign(v) * self.level(v, x) + self.viscous(v)


def element_forces(
    prm: GMSParameters,
    v: float,
    F: ArrayLike,
    slipping: ArrayLike,
    direction: int,
    x: float | None = None,
) -> np.ndarray:
    """The element forces in a hybrid state (friction_gms.c ``gms_element_forces``): a stuck
    element's force is its state F_i; a slipping one's is F_i with ``frictional_lag`` on
    (C finite), else nu_i ``direction`` S(|v|) [N] (S at x with a profile)."""
    F = np.asarray(F, dtype=float)
    slip = np.asarray(slipping, dtype=bool)
    if np.isinf(prm.C):
        S = float(prm.level(abs(v) if direction >= 0 else -abs(v), x))
        return np.where(slip, np.asarray(prm.nu) * direction * S, F)
    return F.copy()


def element_rates(
    prm: GMSParameters,
    v: float,
    F: ArrayLike,
    slipping: ArrayLike,
    direction: int,
    x: float | None = None,
) -> np.ndarray:
    """dF_i/dt in a hybrid state (``gms_derivatives``): k_i v when stuck; slipping with
    frictional lag, (C / S)(nu_i direction S - F_i); without it 0 [N/s]."""
    F = np.asarray(F, dtype=float)
    slip = np.asarray(slipping, dtype=bool)
    stuck_rate = np.asarray(prm.k) * v
    if np.isinf(prm.C):
        return np.where(slip, 0.0, stuck_rate)
    S = float(prm.level(abs(v) if direction >= 0 else -abs(v), x))
    return np.where(slip, prm.C / S * (np.asarray(prm.nu) * direction * S - F), stuck_rate)


def _pieces(
    x: np.ndarray, v: np.ndarray, dt: float, prm: GMSParameters, last_dir: float
) -> tuple[list[float], list[float], list[float], list[float], list[bool], np.ndarray]:
    """Split the intervals into constant-direction pieces.

    Returns per piece: dx, direction, Stribeck level, decay factor, reversal flag; and the
    index of the last piece of each interval.
    """
    v0, v1 = v[:-1], v[1:]
    dx = np.diff(x)
    cross = v0 * v1 < 0
    ni = len(dx)
    npieces = 1 + cross.astype(int)
    last = np.cumsum(npieces) - 1
    first = last - (npieces - 1)
    P = int(last[-1]) + 1 if ni else 0
    pdx, pdir, pspeed, ptau, pxm = np.zeros(P), np.zeros(P), np.zeros(P), np.zeros(P), np.zeros(P)
    x0 = x[:-1]
    # plain intervals
    pl = ~cross
    s = np.sign(v0 + v1)
    s = np.where(s == 0, np.sign(dx), s)
    pdx[first[pl]] = dx[pl]
    pdir[first[pl]] = s[pl]
    pspeed[first[pl]] = 0.5 * (np.abs(v0[pl]) + np.abs(v1[pl]))
    ptau[first[pl]] = dt
    pxm[first[pl]] = x0[pl] + 0.5 * dx[pl]
    # intervals with a velocity zero crossing
    th = np.where(cross, v0 / np.where(cross, v0 - v1, 1.0), 0.0)[cross]
    dxa = v0[cross] * th * dt / 2
    ia, ib = first[cross], last[cross]
    pdx[ia], pdx[ib] = dxa, dx[cross] - dxa
    pdir[ia], pdir[ib] = np.sign(v0[cross]), np.sign(v1[cross])
    pspeed[ia], pspeed[ib] = 0.5 * np.abs(v0[cross]), 0.5 * np.abs(v1[cross])
    ptau[ia], ptau[ib] = th * dt, (1 - th) * dt
    pxm[ia] = x0[cross] + 0.5 * dxa
    pxm[ib] = x0[cross] + dxa + 0.5 * (dx[cross] - dxa)
    S = prm.level(pspeed * np.where(pdir < 0, -1.0, 1.0), pxm)
    if np.isinf(prm.C):
        decay = np.zeros(P)
    else:
        decay = np.exp(-prm.C * ptau / S)
    # reversal flags: direction opposite to the last non-zero direction before the piece
    nz = pdir != 0
    prev = np.where(nz, pdir, np.nan)
    prev = np.concatenate(([last_dir if last_dir != 0 else np.nan], prev[:-1]))
    idx = np.where(~np.isnan(prev), np.arange(P), 0)
    np.maximum.accumulate(idx, out=idx)
    prevf = prev[idx]
    rev = nz & (prevf == -pdir)
    return (pdx.tolist(), pdir.tolist(), S.tolist(), decay.tolist(), rev.tolist(), last)


def _run_element(
    F: float,
    stuck: bool,
    k: float,
    nu: float,
    dxs: list[float],
    dirs: list[float],
    Ss: list[float],
    decays: list[float],
    revs: list[bool],
) -> tuple[list[float], float, bool]:
    """Advance one element over the pieces; its force after every piece."""
    out = [0.0] * len(dxs)
    for j, (dx, s, S, dec, rev) in enumerate(zip(dxs, dirs, Ss, decays, revs, strict=True)):
        if rev:
            stuck = True
        if s != 0.0:
            lim = nu * S
            if stuck:
                F += k * dx
                if s * F >= lim:
                    F = s * lim
                    stuck = False
            else:
                t = s * lim
                F = t + (F - t) * dec
        out[j] = F
    return out, F, stuck


@overload
def gms_force(
    x: ArrayLike,
    v: ArrayLike,
    dt: float,
    params: GMSParameters | Mapping[str, float],
    F0: ArrayLike | None = None,
    return_elements: Literal[False] = False,
) -> np.ndarray: ...
@overload
def gms_force(
    x: ArrayLike,
    v: ArrayLike,
    dt: float,
    params: GMSParameters | Mapping[str, float],
    F0: ArrayLike | None = None,
    *,
    return_elements: Literal[True],
) -> tuple[np.ndarray, np.ndarray]: ...
def gms_force(
    x: ArrayLike,
    v: ArrayLike,
    dt: float,
    params: GMSParameters | Mapping[str, float],
    F0: ArrayLike | None = None,
    return_elements: bool = False,
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """GMS friction force F_f[k] in N along a motion sampled every ``dt``.

    Parameters
    ----------
    x, v : positions [m] and velocities [m/s] at the samples (consistent: x' = v).
    dt : sample interval [s].
    params : :class:`GMSParameters` or FMU-named parameters (effects applied).
    F0 : initial element forces (all elements start stuck); default zeros (virgin state).
    return_elements : also return the element forces, shape (len(x), N).
    """
    prm = params if isinstance(params, GMSParameters) else GMSParameters.from_params(params)
    x = np.asarray(x, dtype=float)
    v = np.asarray(v, dtype=float)
    if x.shape != v.shape or x.ndim != 1 or x.size < 1:
        raise ValueError("friction_gms.py: x and v must be 1-D arrays of the same non-zero length")
    N = len(prm.nu)
    F_init = np.zeros(N) if F0 is None else np.asarray(F0, dtype=float).reshape(N)
    Fe = np.empty((len(x), N))
    Fe[0] = F_init
    if len(x) > 1:
        dxs, dirs, Ss, decs, revs, last = _pieces(x, v, dt, prm, 0.0)
        for i in range(N):
            out, _, _ = _run_element(
                float(F_init[i]), True, prm.k[i], prm.nu[i], dxs, dirs, Ss, decs, revs
            )
            Fe[1:, i] = np.asarray(out)[last]
    F = Fe.sum(axis=1) + prm.viscous(v)
    return (F, Fe) if return_elements else F


class GMSFriction:
    """The same model advanced sample by sample (for closed-loop simulations in Python).

    ``step(x, v)`` moves from the previous sample to (x, v) and returns F_f there.
    """

    def __init__(
        self,
        params: GMSParameters | Mapping[str, float],
        dt: float,
        x0: float = 0.0,
        v0: float = 0.0,
    ) -> None:
        self.prm = (
            params if isinstance(params, GMSParameters) else GMSParameters.from_params(params)
        )
        self.dt = dt
        self._x0, self._v0 = x0, v0
        self.reset()

    def reset(self) -> None:
        """Virgin state: every element stuck at zero force."""
        N = len(self.prm.nu)
        self.F = [0.0] * N
        self.stuck = [True] * N
        self.x, self.v = self._x0, self._v0
        self.last_dir = 0.0

    def step(self, x: float, v: float) -> float:
        """Advance to position ``x`` [m], velocity ``v`` [m/s]; return F_f [N]."""
        prm, dt = self.prm, self.dt
        v0, dx = self.v, x - self.x
        if v0 * v < 0:  # split at the velocity zero crossing
            th = v0 / (v0 - v)
            dxa = v0 * th * dt / 2
            parts = [
                (dxa, v0, 0.5 * abs(v0), th * dt, self.x + 0.5 * dxa),
                (dx - dxa, v, 0.5 * abs(v), (1 - th) * dt, self.x + dxa + 0.5 * (dx - dxa)),
            ]
        else:
            parts = [
                (dx, v0 + v if v0 + v != 0 else dx, 0.5 * (abs(v0) + abs(v)), dt, self.x + 0.5 * dx)
            ]
        dxs, dirs, Ss, decs, revs = [], [], [], [], []
        for pdx, sv, speed, tau, xm in parts:
            d = 1.0 if sv > 0 else (-1.0 if sv < 0 else 0.0)
            S = float(prm.level(speed if d >= 0 else -speed, xm))
            dxs.append(pdx)
            dirs.append(d)
            Ss.append(S)
            decs.append(0.0 if math.isinf(prm.C) else math.exp(-prm.C * tau / S))
            revs.append(d != 0 and d == -self.last_dir)
            if d != 0:
                self.last_dir = d
        for i in range(len(self.F)):
            _, self.F[i], self.stuck[i] = _run_element(
                self.F[i], self.stuck[i], prm.k[i], prm.nu[i], dxs, dirs, Ss, decs, revs
            )
        self.x, self.v = x, v
        return sum(self.F) + (prm.sigma2 + (prm.dsigma2 if v < 0 else 0.0)) * v
