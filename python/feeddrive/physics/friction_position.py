"""Effect ``position_friction``: the friction level varying along the stroke.

The whole Stribeck level of either side is scaled by a smooth profile,
``S(|v|, x) = p(x) S(|v|)`` (break-away ``p(x) F_s``; the viscous term is not scaled), with

    p(x) = 1 + sum_j c_j B_j(x),

``B_j`` a uniform cubic B-spline on n knots ``x_j = x_start + (j - 1) h``,
``h = (x_end - x_start) / (n - 1)``.  The control values beyond the ends are mirrored
(c_0 = c_2, c_{n+1} = c_{n-1}), so p' = 0 at both ends, and p is constant outside
[x_start, x_end]: p is C1 (C2 inside), linear in c (identification is linear least squares
on :meth:`FrictionProfile.basis`), and stays within [1 + min c, 1 + max c] (convex hull).
C twin: fmu_src/physics/friction_position.c (same arithmetic, so both agree to rounding).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

#: Knot slots in the FMU (friction_profile.c[1..16]).
N_KNOTS_MAX = 16
#: Allowed range of a knot value c_j (modelDescription.xml min/max): p >= 0.1.
C_RANGE = (-0.9, 4.0)


def _segments(
    x: ArrayLike, x_start: float, h: float, n: int
) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    """Segment index k and the four B-spline weights at x (friction_position.c)."""
    u = (np.asarray(x, dtype=float) - x_start) / h
    u = np.where(u > 0.0, u, 0.0)  # NaN -> 0 as in C
    u = np.minimum(u, float(n - 1))
    k = np.minimum(np.floor(u).astype(int), n - 2)
    t = u - k
    w0 = (1.0 - t) * (1.0 - t) * (1.0 - t) / 6.0
    w1 = (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0
    w2 = (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0
    w3 = t * t * t / 6.0
    return k, (w0, w1, w2, w3)


def _mirror(i: np.ndarray, n: int) -> np.ndarray:
    i = np.abs(i)
    return np.where(i > n - 1, 2 * (n - 1) - i, i)


def profile_basis(x: ArrayLike, x_start: float, x_end: float, n: int) -> np.ndarray:
    """The n basis functions B_j(x) (mirrored ends, constant outside), shape (len(x), n):
    p(x) = 1 + basis @ c.  Each row sums to 1."""
    if not x_end > x_start or n < 2:
        raise ValueError(
            f"friction_position.py: need x_end > x_start and n >= 2, got "
            f"[{x_start}, {x_end}], n = {n}"
        )
    x = np.atleast_1d(np.asarray(x, dtype=float))
    k, w = _segments(x, x_start, (x_end - x_start) / (n - 1), n)
    B = np.zeros((len(x), n))
    rows = np.arange(len(x))
    for j, wj in enumerate(w):
        np.add.at(B, (rows, _mirror(k - 1 + j, n)), wj)
    return B


@dataclass(frozen=True)
class FrictionProfile:
    """p(x) of ``position_friction``: knots from ``x_start`` to ``x_end`` [m], values ``c`` [-]."""

    x_start: float
    x_end: float
    c: tuple[float, ...]

    def __post_init__(self) -> None:
        if not self.x_end > self.x_start or not 2 <= len(self.c) <= N_KNOTS_MAX:
            raise ValueError(
                f"friction_position.py: need x_end > x_start and 2..{N_KNOTS_MAX} "
                f"knots, got [{self.x_start}, {self.x_end}] with {len(self.c)}"
            )

    @property
    def n(self) -> int:
        return len(self.c)

    @property
    def h(self) -> float:
        """Knot spacing [m]."""
        return (self.x_end - self.x_start) / (self.n - 1)

    @property
    def knots(self) -> np.ndarray:
        """Knot positions [m]."""
        return self.x_start + self.h * np.arange(self.n)

    @classmethod
    def from_params(cls, params: Mapping[str, Any]) -> FrictionProfile:
        """From FMU-named parameters ``friction_profile.*`` (the FMU's defaults when absent)."""
        n = int(params.get("friction_profile.n", N_KNOTS_MAX))
        return cls(
            x_start=float(params.get("friction_profile.x_start", 0.0)),
            x_end=float(params.get("friction_profile.x_end", 0.3)),
            c=tuple(float(params.get(f"friction_profile.c[{j}]", 0.0)) for j in range(1, n + 1)),
        )

    def parameters(self) -> dict[str, float | int]:
        """The FMU parameters of this profile (unused knot slots 0)."""
        out: dict[str, float | int] = {
            "friction_profile.x_start": float(self.x_start),
            "friction_profile.x_end": float(self.x_end),
            "friction_profile.n": self.n,
        }
        for j in range(1, N_KNOTS_MAX + 1):
            out[f"friction_profile.c[{j}]"] = float(self.c[j - 1]) if j <= self.n else 0.0
        return out

    def basis(self, x: ArrayLike) -> np.ndarray:
        """:func:`profile_basis` of this profile's knots."""
        return profile_basis(x, self.x_start, self.x_end, self.n)

    def __call__(self, x: ArrayLike) -> np.ndarray:
        """p(x) [-], evaluated as friction_position.c does."""
        n = self.n
        c = np.asarray(self.c, dtype=float)
        k, (w0, w1, w2, w3) = _segments(x, self.x_start, self.h, n)
        s = (
            w0 * c[_mirror(k - 1, n)]
            + w1 * c[_mirror(k, n)]
            + w2 * c[_mirror(k + 1, n)]
            + w3 * c[_mirror(k + 2, n)]
        )
        return 1.0 + s
