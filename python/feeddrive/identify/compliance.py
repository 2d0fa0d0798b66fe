"""Compliance (effect ``compliance``): the load's natural frequency f, damping ratio zeta and
mass m2 from the force residual of a rigid model along measured runs.

With the encoder on the slide and a load m2 on a spring-damper (``feeddrive.physics.compliance``)
Eq. 1 of the slide reads ``m a = F_slide - m2 a2`` with ``a2 = H(s) a``,
``H(s) = (2 zeta w s + w^2) / (s^2 + 2 zeta w s + w^2)``.  Filtered with the acceleration
estimator's kernel K (which commutes with H), the rigid model's residual
``y = K F_slide - m a_K`` is therefore

    y = m2 H(s) a_K  (+ dm a_K when the model's mass is off too),

plus the load's free response from each run's first filtered sample (its state there, half a
kernel into the run, is not measured: two nuisance coefficients per run), plus what a change
of the run's estimated GMS start forces makes of the friction over its first samples (with
pre-rolling on: :mod:`feeddrive.physics.gms_start` estimates them on the rigid residual,
where the load's own response at the start is still in it, so they are free again here, one
nuisance coefficient per element and run, their sensitivity ``GMSStart.basis``; fixed at the
rigid estimate, the start forces take up part of the load's first oscillations and bias its
damping), linear in (m2, dm) for fixed (f, zeta): a variable-projection fit, a grid over
f in [20, 200] Hz (the FMU's range) and zeta in [0.01, 1] searched by the explained energy,
the best point refined by Nelder-Mead in (log f, log zeta).  Excitation must reach f: the
steps of a trapezoidal move's acceleration (point-to-point moves) or a PRBS do; a slow
sinusoid does not (the load then only adds mass).  The Savitzky-Golay window bounds what can
be seen: its kernel attenuates f above about (polyorder + 1) / (3.2 window Ts).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..data import Run
from ..fits.compliance import (
    F_GRID,
    SEARCH_STRIDE,
    ZETA_GRID,
    ZETA_RANGE,
    ComplianceFit,
    fit_compliance,
    nuisance_columns,
    start_columns,
)
from ..physics import (
    DEFAULT_V_STICK,
    applied_force,
    compile,
    force_residual,
    friction_velocity,
    gms_force,
    held_current,
    karnopp_friction,
    measured_motion,
    run_load,
    started_friction,
)
from ..physics.params import HasFmuParameters
from ..signals import odd_window, run_label, sample_time

__all__ = [
    "F_GRID",
    "SEARCH_STRIDE",
    "ZETA_GRID",
    "ZETA_RANGE",
    "ComplianceFit",
    "RigidResidual",
    "fit_compliance",
    "identify_compliance",
    "nuisance_columns",
    "rigid_parts",
    "rigid_residual",
    "start_columns",
]


@dataclass
class RigidResidual:
    """The rigid model's residual along one run and what it was computed with."""

    a: np.ndarray  #: filtered measured acceleration [m/s^2] (NaN near the ends)
    r: np.ndarray  #: residual of the model without its compliance [N]
    Ts: float  #: sample interval [s]
    #: (n, N) the filtered friction's change per newton of each estimated GMS start force
    #: (zeros once the start no longer acts), or None (pre-rolling off)
    start_basis: np.ndarray | None = field(default=None)


def rigid_parts(
    run: Run, model: HasFmuParameters, window_s: float = 0.02, polyorder: int = 3
) -> RigidResidual:
    """The filtered measured acceleration and the residual of ``model`` *without* its
    compliance, ``K (K_f(x) i - F_cg - F_load - offset - F_f) - m a_K`` (GMS friction along
    the measured motion with pre-rolling on, started from the element forces that best
    explain the first samples, :func:`feeddrive.physics.started_friction`, with their
    sensitivity; else Eq. 12 with Karnopp stiction).  The run needs a measured current
    ``i``."""
    label = run_label(run)
    if run.i is None:
        raise ValueError(f"{label}: identify_compliance needs a measured current column i")
    P = compile(model)
    Ts = sample_time(run.time, label=label)
    x = np.asarray(run.x, dtype=float)
    w = odd_window(int(round(window_s / Ts)), run.n)
    v, a, K = measured_motion(x, Ts, w, polyorder)
    F_load, _ = run_load(run)
    F_app = applied_force(P.K_f(x) * held_current(run.i), P.F_cg(x), F_load, P.F_offset)
    if P.prerolling:
        v_f = friction_velocity(x, Ts, w, polyorder)
        F_f = gms_force(x, v_f, Ts, P.friction)
        _, start, r = started_friction(
            x, v_f, Ts, P.friction, force_residual(F_app, F_f, a, P.m, K), K, F_f
        )
        basis = start.full_basis(len(x)) if start.basis is not None else None
        return RigidResidual(a, r, Ts, basis)
    F_f, _ = karnopp_friction(v, F_app, P.friction, DEFAULT_V_STICK)
    return RigidResidual(a, force_residual(F_app, F_f, a, P.m, K), Ts)


def rigid_residual(
    run: Run, model: HasFmuParameters, window_s: float = 0.02, polyorder: int = 3
) -> tuple[np.ndarray, np.ndarray, float]:
    """(a_K, y, Ts) of :func:`rigid_parts`."""
    p = rigid_parts(run, model, window_s, polyorder)
    return p.a, p.r, p.Ts


def identify_compliance(
    runs: list[Run], model: HasFmuParameters, fit_mass: bool = False, window_s: float = 0.02
) -> ComplianceFit:
    """f, zeta, m2 (module docstring) from measured runs (encoder on the slide) and a model of
    the rest of the drive (its own compliance, if any, is ignored): :func:`rigid_parts` per
    run, then :func:`fit_compliance` over all of them, the GMS start forces refitted with
    the load."""
    if not runs:
        raise ValueError("identify_compliance: no runs given")
    parts = [rigid_parts(run, model, window_s) for run in runs]
    return fit_compliance(
        [p.a for p in parts],
        [p.r for p in parts],
        [p.Ts for p in parts],
        fit_mass=fit_mass,
        nuisance=[p.start_basis for p in parts],
    )
