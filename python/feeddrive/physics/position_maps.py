"""Position maps of Eqs. 6-7 in SI: cogging force F_cg(x) [N] and force constant K_f(x) [N/A].

Both are a polynomial in x (the "aperiodic" part) plus a Fourier series whose terms each carry
their own wavelength (the "periodic" part).  Parameters use FMU names (``cogging.c[0]``,
``cogging.lambda[1]``, ``cogging.a[1]``, ``cogging.b[1]``).  As the map effects' entries
of fmu_src/physics/position_maps.c compile a map: a switched-off part is dropped, except the
constant ``ripple.c[0]`` (``ripple_aperiodic`` off means K_f = c0 + Fourier); harmonic slots with
a = b = 0 are skipped.  C twin:
fmu_src/physics/position_maps.c (the FMU evaluates at x clamped to the stroke, see
:meth:`feeddrive.physics.params.PlantParameters.K_f`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..effects import position_map_effects
from ..paper import N_HARMONICS, STROKE

#: Highest polynomial power per map in the FMU.
POLY_ORDER = {"cogging": 3, "ripple": 2}
#: The effect switch of each map's (periodic, aperiodic) part.
MAP_EFFECTS: dict[str, tuple[str, str]] = position_map_effects()


@dataclass(frozen=True)
class PositionMap:
    """sum_k c[k] x^k + sum_j a[j] cos(2 pi x / lambda[j]) + b[j] sin(2 pi x / lambda[j])."""

    c: tuple[float, ...]
    wavelengths: tuple[float, ...] = ()
    a: tuple[float, ...] = ()
    b: tuple[float, ...] = ()

    @classmethod
    def from_parameters(
        cls, name: str, params: Mapping[str, float], periodic: bool = True, aperiodic: bool = True
    ) -> PositionMap:
        """Map ``name`` ("cogging" or "ripple") from FMU-named parameters with the given
        parts on (missing names count as zero; a used slot needs its wavelength)."""
        if name not in POLY_ORDER:
            raise ValueError(f"position map {name!r}: allowed 'cogging' or 'ripple'")
        c = tuple(
            float(params.get(f"{name}.c[{k}]", 0.0))
            if aperiodic or (name == "ripple" and k == 0)
            else 0.0
            for k in range(POLY_ORDER[name] + 1)
        )
        lam, a, b = [], [], []
        if periodic:
            for j in range(1, N_HARMONICS + 1):
                aj = float(params.get(f"{name}.a[{j}]", 0.0))
                bj = float(params.get(f"{name}.b[{j}]", 0.0))
                if aj == 0.0 and bj == 0.0:
                    continue
                lam.append(float(params[f"{name}.lambda[{j}]"]))
                a.append(aj)
                b.append(bj)
        return cls(c=c, wavelengths=tuple(lam), a=tuple(a), b=tuple(b))

    def __call__(self, x: ArrayLike) -> np.ndarray:
        """The map at positions ``x`` [m] (no clamping)."""
        x = np.asarray(x, dtype=float)
        out = np.zeros_like(x)
        for k, ck in enumerate(self.c):
            out = out + ck * x**k
        for lam, aj, bj in zip(self.wavelengths, self.a, self.b, strict=True):
            th = 2.0 * np.pi * x / lam
            out = out + aj * np.cos(th) + bj * np.sin(th)
        return out


def evaluate(
    name: str,
    x: ArrayLike,
    params: Mapping[str, float],
    periodic: bool = True,
    aperiodic: bool = True,
    clamp: bool = True,
) -> np.ndarray:
    """Map ``name`` ("cogging" [N] or "ripple" [N/A]) at ``x`` [m] from FMU-named parameters.

    ``periodic``/``aperiodic`` include the Fourier / polynomial part (see
    :meth:`PositionMap.from_parameters`); ``clamp`` evaluates at x clamped to
    [stroke.x_min, stroke.x_max] as the FMU does.
    """
    x = np.asarray(x, dtype=float)
    if clamp:
        x = np.clip(x, params.get("stroke.x_min", STROKE[0]), params.get("stroke.x_max", STROKE[1]))
    return PositionMap.from_parameters(name, params, periodic, aperiodic)(x)


def cogging(x: ArrayLike, params: Mapping[str, float], **kw: bool) -> np.ndarray:
    """F_cg(x) [N] (Eq. 6); positive pushes toward -x."""
    return evaluate("cogging", x, params, **kw)


def force_constant(x: ArrayLike, params: Mapping[str, float], **kw: bool) -> np.ndarray:
    """K_f(x) [N/A] (Eq. 7)."""
    return evaluate("ripple", x, params, **kw)


#: A position map given either as FMU parameters or as a callable x [m] -> value.
MapSpec = Mapping[str, float] | Callable[[np.ndarray], np.ndarray]


def eval_map(spec: MapSpec, name: str, x: ArrayLike) -> np.ndarray:
    """K_f ('ripple') or F_cg ('cogging') at x from FMU parameters (clamped to the stroke,
    both parts on) or from a callable."""
    if callable(spec):
        return np.asarray(spec(np.asarray(x, dtype=float)), dtype=float)
    return evaluate(name, x, spec, clamp=True)
