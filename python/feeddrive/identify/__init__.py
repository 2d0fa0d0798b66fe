r"""Identification procedures of the paper (Secs. 2.2-2.4) on measured runs, numpy/scipy only.

Every ``identify_*`` function takes :class:`feeddrive.data.Run` objects (the ``fit_*``
variants plain arrays) and returns a small dataclass with ``parameters`` in FMU naming and SI,
standard errors where they can be stated, and fit diagnostics.

| module          | procedure                                   | parameters                          |
|-----------------|---------------------------------------------|-------------------------------------|
| current_loop    | PRBS, ARX + output error, order selection   | current.a[1..5], b[0..5]            |
| position_maps   | Eqs. 4-7 (constant-speed runs, loads)       | ripple.\*, cogging.\*               |
| dstft           | DSTFT of Sec. 2.3.2 (ShortTimeFFT)          | (analysis)                          |
| stribeck        | Eq. 13, fit of Eq. 12, asymmetry            | friction.F_s/F_c/V_s/delta/sigma2   |
| mass            | Eq. 1 least squares, open-loop run          | m                                   |
| attraction      | Eq. 14 (non-reversing run)                  | friction.C                          |
| prerolling      | Eqs. 15-18 (two periodic runs)              | friction.N, nu[i], k[i]             |
| compliance      | Eq. 1 residual, H(s) of the load, grid + NM | compliance.f/zeta/m2                |
"""

from .attraction import AttractionFit, fit_attraction, identify_attraction, simulate_lag
from .compliance import (
    ComplianceFit,
    RigidResidual,
    fit_compliance,
    identify_compliance,
    rigid_parts,
    rigid_residual,
)
from .current_loop import CurrentLoopFit, fit_current_loop, identify_current_loop
from .dstft import DSTFT, dstft
from .mass import MassFit, fit_mass, identify_mass
from .position_maps import (
    MapFit,
    MapSamples,
    PositionMapsFit,
    fit_map,
    identify_position_maps,
    map_samples,
)
from .prerolling import (
    PrerollingFit,
    fit_knots,
    fit_weights,
    half_cycles,
    identify_prerolling,
    maxwell_slip,
)
from .stribeck import StribeckFit, StribeckPoints, fit_stribeck, identify_stribeck, stribeck_points

__all__ = [
    "ComplianceFit",
    "RigidResidual",
    "fit_compliance",
    "identify_compliance",
    "rigid_parts",
    "rigid_residual",
    "AttractionFit",
    "fit_attraction",
    "identify_attraction",
    "simulate_lag",
    "CurrentLoopFit",
    "fit_current_loop",
    "identify_current_loop",
    "DSTFT",
    "dstft",
    "MassFit",
    "fit_mass",
    "identify_mass",
    "MapFit",
    "MapSamples",
    "PositionMapsFit",
    "fit_map",
    "identify_position_maps",
    "map_samples",
    "PrerollingFit",
    "fit_knots",
    "fit_weights",
    "half_cycles",
    "identify_prerolling",
    "maxwell_slip",
    "StribeckFit",
    "StribeckPoints",
    "fit_stribeck",
    "identify_stribeck",
    "stribeck_points",
]
