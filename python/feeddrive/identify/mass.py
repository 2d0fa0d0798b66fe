"""Moving mass from an open-loop force experiment (Sec. 2.4.3, last paragraph; Eq. 1).

    m a = K_f(x) i - F_cg(x) - F_f(v) - F_load

v and a come from a Savitzky-Golay differentiator of the measured position; the force side
is smoothed by the kernel that differentiator applies to the true acceleration (see
``feeddrive.signals.matched_acceleration``), so both sides see exactly the same averaging.  Samples
slower than ``v_min`` or within ``reversal_skip`` of travel after a reversal are left out
(there pre-rolling and frictional lag make F_f a function of the history, not of v), and so
is every sample whose filter window reaches one of them, and half a window at both ends.

- ``friction='known'``: F_f = Eq. 12 with the given Stribeck parameters (plus the FMU's
  asymmetry terms when present); one unknown, m (plus an optional constant force).
- ``friction='coulomb_viscous'``: F_f = F_c sgn(v) + sigma2 v estimated jointly with m.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..data import Run
from ..physics import FrictionCurve, MapSpec, eq1_terms
from ..signals import apply_kernel, run_label
from ._signals import current, lstsq_with_stderr, signal


@dataclass
class MassFit:
    """Least-squares mass (and friction terms when estimated)."""

    parameters: dict[str, float]  #: "m" [kg]; "friction.F_c", "friction.sigma2", "offset.F"
    stderr: dict[str, float]  #: least-squares, scaled by the filter's correlation length
    rms_residual: float  #: force residual [N]
    n_used: int  #: samples in the regression
    window: int  #: Savitzky-Golay window [samples]
    force_rms: float  #: rms of m a over the used samples [N] (excitation level)


def steady_friction_from(params: Mapping[str, float], v: np.ndarray) -> np.ndarray:
    """Eq. 12 from FMU parameters, with asymmetry.dF / dsigma2 applied for v < 0."""
    return FrictionCurve.from_params(params).steady(v)


def fit_mass(
    time: np.ndarray,
    x: np.ndarray,
    i: np.ndarray,
    force_constant: MapSpec,
    cogging: MapSpec,
    F_load: np.ndarray | float = 0.0,
    friction: str | Mapping[str, float] = "coulomb_viscous",
    window: int = 41,
    v_min: float = 0.01,
    reversal_skip: float = 1e-3,
    fit_offset: bool = False,
    current_timing: str = "held",
) -> MassFit:
    """Least-squares m from sampled x [m], i [A] (see module docstring).

    Parameters
    ----------
    force_constant, cogging : K_f and F_cg maps (FMU parameters or callables).
    F_load : known external force [N] (array or constant).
    friction : 'coulomb_viscous' (jointly estimated) or a mapping with friction.F_s, F_c,
        V_s, delta, sigma2 (known, Eq. 12).
    window : Savitzky-Golay window [samples] (41 = 20 ms at 0.5 ms).
    v_min : samples with |v| < v_min [m/s] are excluded.
    reversal_skip : samples within this travel [m] after a velocity sign change (or the run
        start) are excluded: pre-rolling (up to 2 Delta_N ~ 0.23 mm) and the frictional lag
        make friction there a function of the history, not of v.
    current_timing : 'held' (i[k] acts over [t_k, t_k+1), Eq. 2), 'held_previous' (i[k]
        acted over [t_k-1, t_k): recorded one sample late) or 'sampled' (continuous current);
        see ``feeddrive.physics.held_current``.  A one-sample error here biases m by ~1 % on a
        square-wave run.
    fit_offset : also estimate a constant force offset.F, taken to act like F_load
        (m a = ... - F_load - offset.F).
    """
    t = np.asarray(time, dtype=float)
    x = np.asarray(x, dtype=float)
    force, a, v, K, _Ts = eq1_terms(
        t, x, i, force_constant, cogging, F_load, window, current_timing
    )
    cols, names = [a], ["m"]
    if isinstance(friction, str):
        if friction != "coulomb_viscous":
            raise ValueError(
                f"mass: friction must be 'coulomb_viscous' or a parameter mapping, got {friction!r}"
            )
        cols += [apply_kernel(np.sign(v), K), apply_kernel(v, K)]
        names += ["friction.F_c", "friction.sigma2"]
    else:
        force = force - steady_friction_from(friction, v)
    if fit_offset:
        cols.append(np.ones_like(x))
        names.append("offset.F")
    y = apply_kernel(force, K)
    seg_id = np.concatenate(([0], np.cumsum(np.diff(np.sign(v)) != 0)))
    starts = np.concatenate(([0], np.flatnonzero(np.diff(seg_id)) + 1))
    travel = np.abs(x - x[starts][seg_id])
    bad = (np.abs(v) < v_min) | (travel < reversal_skip)
    # the filtered value at k sees samples k +- len(K)/2: keep that far from excluded ones
    bad = np.convolve(bad.astype(float), np.ones(len(K)), mode="same") > 0
    use = ~bad & np.all(np.isfinite(np.column_stack(cols + [y])), axis=1)
    if use.sum() < 3 * len(cols):
        raise ValueError(f"mass: only {int(use.sum())} samples faster than v_min = {v_min:g} m/s")
    A = np.column_stack(cols)[use]
    theta, se, r = lstsq_with_stderr(A, y[use])
    se = se / np.sqrt(np.sum(K**2))  # residuals are filtered noise: correlation length 1/sum K^2
    return MassFit(
        parameters={n: float(t_) for n, t_ in zip(names, theta, strict=True)},
        stderr={n: float(s) for n, s in zip(names, se, strict=True)},
        rms_residual=float(np.sqrt(np.mean(r**2))),
        n_used=int(use.sum()),
        window=window,
        force_rms=float(theta[0] * np.sqrt(np.mean(a[use] ** 2))),
    )


def identify_mass(
    run: Run,
    force_constant: MapSpec,
    cogging: MapSpec,
    friction: str | Mapping[str, float] = "coulomb_viscous",
    dc_gain: float | None = None,
    **kw,
) -> MassFit:
    """:func:`fit_mass` on a run with columns time, x, i (F_load used when present).

    ``dc_gain``: for a run without a current column, i = dc_gain * u (the recording format).
    """
    label = run_label(run)
    F = run.F_load if run.F_load is not None else 0.0
    try:
        return fit_mass(
            run.time,
            signal(run, "x"),
            current(run, dc_gain),
            force_constant,
            cogging,
            F,
            friction,
            **kw,
        )
    except ValueError as e:
        raise ValueError(f"{label}: {e}") from None
