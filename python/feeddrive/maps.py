"""Position maps of Eqs. 6-7 in SI: cogging force F_cg(x) and force constant K_f(x).

Both are a polynomial in x (the "aperiodic" part) plus a Fourier series whose terms each
carry their own wavelength (the "periodic" part).  Parameters use FMU names, e.g.
``cogging.c[0]``, ``cogging.lambda[1]``, ``cogging.a[1]``, ``cogging.b[1]``.
The FMU evaluates the maps at x clamped to the stroke; so does :func:`evaluate`.
"""
from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .paper import N_HARMONICS

POLY_ORDER = {"cogging": 3, "ripple": 2}


def evaluate(name: str, x: np.ndarray | float, params: Mapping[str, float],
             periodic: bool = True, aperiodic: bool = True, clamp: bool = True) -> np.ndarray:
    """Evaluate map ``name`` ("cogging" [N] or "ripple" [N/A]) at positions ``x`` [m].

    Parameters
    ----------
    name : "cogging" or "ripple".
    x : positions in metres.
    params : FMU-named parameters (missing harmonic slots count as zero amplitude).
    periodic, aperiodic : include the Fourier / polynomial part.  For "ripple" the
        constant c[0] is always kept (``ripple_aperiodic`` off means K_f = c0 + Fourier).
    clamp : evaluate at x clamped to [stroke.x_min, stroke.x_max] as the FMU does.
    """
    x = np.asarray(x, dtype=float)
    if clamp:
        x = np.clip(x, params.get("stroke.x_min", 0.0), params.get("stroke.x_max", 0.3))
    out = np.zeros_like(x)
    for k in range(POLY_ORDER[name] + 1):
        c = params.get(f"{name}.c[{k}]", 0.0)
        if aperiodic or (name == "ripple" and k == 0):
            out = out + c * x**k
    if periodic:
        for j in range(1, N_HARMONICS + 1):
            a = params.get(f"{name}.a[{j}]", 0.0)
            b = params.get(f"{name}.b[{j}]", 0.0)
            if a == 0.0 and b == 0.0:
                continue
            th = 2.0 * np.pi * x / params[f"{name}.lambda[{j}]"]
            out = out + a * np.cos(th) + b * np.sin(th)
    return out


def cogging(x: np.ndarray | float, params: Mapping[str, float], **kw: bool) -> np.ndarray:
    """F_cg(x) [N] (Eq. 6); positive pushes toward -x."""
    return evaluate("cogging", x, params, **kw)


def force_constant(x: np.ndarray | float, params: Mapping[str, float], **kw: bool) -> np.ndarray:
    """K_f(x) [N/A] (Eq. 7)."""
    return evaluate("ripple", x, params, **kw)
