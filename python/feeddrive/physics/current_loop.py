"""The sampled current loop G(z) of Eq. 2 in SI (u [V] -> i [A]).

    i[k] = sum_{j=1..5} a_j i[k-j] + sum_{j=0..5} b_j u[k-j],   G(1) = sum b / (1 - sum a)

With the dynamics off (the effect ``current_dynamics``, the plant structure
:attr:`~feeddrive.effects.Structure.CURRENT_FILTER`): i = G(1) u at once.  C twin:
fmu_src/physics/current_loop.c.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.signal import lfilter, lfiltic

from ..effects import Structure, structure_on

N_CURRENT_A = 5  #: current.a[1..5]
N_CURRENT_B = 6  #: current.b[0..5]


@dataclass(frozen=True)
class CurrentLoop:
    """Eq. 2's coefficients, the DC gain and whether the dynamics are on."""

    a: tuple[float, ...]  #: current.a[1..5]
    b: tuple[float, ...]  #: current.b[0..5]
    dynamics: bool = True

    @classmethod
    def from_parameters(cls, params: Mapping[str, float]) -> CurrentLoop:
        """From ``current.a/b`` and the switch that selects the dynamics (missing names are
        0 / on)."""
        return cls(
            a=tuple(float(params.get(f"current.a[{j}]", 0.0)) for j in range(1, N_CURRENT_A + 1)),
            b=tuple(float(params.get(f"current.b[{j}]", 0.0)) for j in range(N_CURRENT_B)),
            dynamics=structure_on(params, Structure.CURRENT_FILTER),
        )

    @property
    def G1(self) -> float:
        """DC gain G(1) [A/V] (1.1260 A/V for Eq. 2)."""
        return sum(self.b) / (1.0 - sum(self.a))

    def polynomials(self) -> tuple[np.ndarray, np.ndarray]:
        """Numerator and denominator of G(z) in powers of z^-1, trailing zeros removed;
        (G(1),), (1,) when the dynamics are off."""
        if not self.dynamics:
            return np.array([self.G1]), np.array([1.0])
        den = np.trim_zeros(np.concatenate(([1.0], -np.asarray(self.a))), "b")
        num = np.trim_zeros(np.asarray(self.b, dtype=float), "b")
        return (num if num.size else np.zeros(1)), den

    def current(self, u: ArrayLike) -> np.ndarray:
        """i[k] for the samples u[k] (filter from rest, as fmu's history at u = 0)."""
        num, den = self.polynomials()
        return lfilter(num, den, np.asarray(u, dtype=float))


def current_loop_polynomials(params: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """(num, den) of G(z) in powers of z^-1 from FMU-named parameters (see :class:`CurrentLoop`)."""
    return CurrentLoop.from_parameters(params).polynomials()


def current_loop_dc_gain(params: Mapping[str, float]) -> float:
    """G(1) [A/V] from FMU-named parameters."""
    return CurrentLoop.from_parameters(params).G1


def simulate_current(
    a: ArrayLike,
    b: ArrayLike,
    u: ArrayLike,
    i_init: ArrayLike | None = None,
    u_init: ArrayLike | None = None,
) -> np.ndarray:
    """i[k] = sum a_j i[k-j] + sum b_j u[k-j] for any a (i lags 1..) and b (u lags 0..).

    ``i_init``/``u_init`` are the samples just before ``u[0]`` in time order (the last
    entry is the one immediately before); missing history counts as zero.
    """
    den = np.concatenate(([1.0], -np.asarray(a, dtype=float)))
    num = np.asarray(b, dtype=float)
    if num.size == 0:
        return np.zeros(len(np.asarray(u)))
    zi = None
    if i_init is not None or u_init is not None:
        yh = np.zeros(0) if i_init is None else np.asarray(i_init, dtype=float)[::-1]
        xh = np.zeros(0) if u_init is None else np.asarray(u_init, dtype=float)[::-1]
        zi = lfiltic(num, den, yh, xh)
        return lfilter(num, den, np.asarray(u, dtype=float), zi=zi)[0]
    return lfilter(num, den, np.asarray(u, dtype=float))
