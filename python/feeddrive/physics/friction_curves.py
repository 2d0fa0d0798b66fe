"""The Stribeck curve (Eq. 10) and the steady sliding friction (Eq. 12) in SI.

The one Python statement of S(|v|); the GMS (:mod:`.friction_gms`), the static friction
(:mod:`.friction_static`), identification, diagnosis and feedforward all call it.
C twin: ``friction_level`` in fmu_src/physics/friction_levels.c.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike


def stribeck_level(
    speed: ArrayLike, F_s: ArrayLike, F_c: ArrayLike, V_s: float, delta: float
) -> np.ndarray:
    """S(|v|) = F_c + (F_s - F_c) exp(-|v/V_s|^delta) [N]; S(0) = F_s."""
    s = np.abs(np.asarray(speed, dtype=float))
    Fc = np.asarray(F_c, dtype=float)
    return Fc + (np.asarray(F_s, dtype=float) - Fc) * np.exp(-np.power(s / V_s, delta))


def stribeck_drop(v: ArrayLike, V_s: float, delta: float) -> np.ndarray:
    """The Stribeck shape sgn(v) exp(-|v/V_s|^delta) [-] (the regressor of F_s - F_c)."""
    v = np.asarray(v, dtype=float)
    return np.sign(v) * np.exp(-np.power(np.abs(v) / V_s, delta))


def steady_friction(
    v: ArrayLike, F_s: ArrayLike, F_c: ArrayLike, V_s: float, delta: float, sigma2: ArrayLike
) -> np.ndarray:
    """Steady sliding friction s(v) + sigma2 v (Eq. 12) [N]; 0 at v = 0 (sgn(0) = 0)."""
    v = np.asarray(v, dtype=float)
    return np.sign(v) * stribeck_level(v, F_s, F_c, V_s, delta) + sigma2 * v


@dataclass(frozen=True)
class FrictionCurve:
    """The steady friction of both sides: for v < 0 the levels are F_s + dF, F_c + dF and the
    viscous coefficient sigma2 + dsigma2 (``asymmetric_friction``)."""

    F_s: float
    F_c: float
    V_s: float
    delta: float
    sigma2: float
    dF: float = 0.0
    dsigma2: float = 0.0

    @classmethod
    def from_params(cls, params: Mapping[str, float]) -> FrictionCurve:
        """From FMU-named parameters as given (``asymmetry.*`` default 0; no switches)."""
        return cls(
            F_s=float(params["friction.F_s"]),
            F_c=float(params["friction.F_c"]),
            V_s=float(params["friction.V_s"]),
            delta=float(params["friction.delta"]),
            sigma2=float(params["friction.sigma2"]),
            dF=float(params.get("asymmetry.dF", 0.0)),
            dsigma2=float(params.get("asymmetry.dsigma2", 0.0)),
        )

    def level(self, v: ArrayLike) -> np.ndarray:
        """S(|v|) of the side of v [N]; S(0) = F_s."""
        v = np.asarray(v, dtype=float)
        neg = v < 0
        return stribeck_level(
            v, self.F_s + self.dF * neg, self.F_c + self.dF * neg, self.V_s, self.delta
        )

    def viscous(self, v: ArrayLike) -> np.ndarray:
        """sigma2 v, with sigma2 + dsigma2 for v < 0 [N]."""
        v = np.asarray(v, dtype=float)
        return (self.sigma2 + self.dsigma2 * (v < 0)) * v

    def sliding(self, v: ArrayLike) -> np.ndarray:
        """s(v) = sgn(v) S(|v|) [N] (Eq. 10 with the side's levels)."""
        return np.sign(v) * self.level(v)

    def steady(self, v: ArrayLike) -> np.ndarray:
        """Steady sliding friction s(v) + sigma2 v (Eq. 12) [N]; 0 at v = 0."""
        return self.sliding(v) + self.viscous(v)
