"""The friction-level profile p(x) of ``position_friction`` from sliding runs.

On constant-speed runs (or slow sinusoids) away from reversals the friction is the sliding
level times the profile, ``F_f = p(x) sgn(v) S(|v|) + sigma2(v) v`` (Eq. 12 with
:mod:`feeddrive.physics.friction_position`), and Eq. 1 gives F_f on the data:
``K (K_f(x) i - F_cg(x) - F_e) - m a`` (:func:`feeddrive.physics.eq1_terms`, K the
acceleration estimator's kernel).  With the levels known (Stribeck step) and
``p = 1 + sum_j c_j B_j(x)`` this is linear in c:

    K (F_app - sigma2 v) - m a - K L  =  sum_j c_j K (L B_j(x)),    L = sgn(v) S(|v|),

solved by least squares over the samples faster than ``v_min`` and more than
``reversal_skip`` of travel after a reversal (pre-rolling and lag make friction there a
matter of history), with n uniform knots over the stroke the runs slid over.

A profile and the level trade off (p -> p/s, F_s, F_c -> s F_s, s F_c give the same
friction), so the fit is normalised: the **median of p over the used samples is 1** and the
levels carry the scale (a local patch of wear or lubrication leaves most of the stroke at
the nominal level; the Stribeck step, which averages over position, saw the level times the
mean of p).  The rescaled F_s, F_c (and asymmetry.dF) are part of the result.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..data import Run
from ..effects import Structure, is_on, owner, structure_off
from ..physics import FrictionProfile, GMSParameters, eq1_terms, profile_basis, run_load
from ..physics.friction_position import C_RANGE, N_KNOTS_MAX
from ..signals import apply_kernel, run_label
from ._signals import current, signal

#: The friction level's direction asymmetry [N]: scaled with the levels when its effect is on.
ASYMMETRY = "asymmetry.dF"

#: Samples slower than this [m/s] are left out (stick, pre-rolling).
V_MIN = 2e-3
#: Travel after a reversal [m] left out (pre-rolling up to 2 Delta_N ~ 0.23 mm, lag).
REVERSAL_SKIP = 1e-3


@dataclass
class PositionFrictionFit:
    """The identified profile, the level scale it moved into F_s, F_c, and fit statistics."""

    profile: FrictionProfile
    scale: float  #: median of the raw p; the levels were multiplied by it
    parameters: dict[str, Any]  #: friction_profile.*, and friction.F_s, F_c (+ asymmetry.dF)
    rms_residual: float  #: [N]
    n_used: int
    runs: list[str]


def _run_rows(
    run: Run,
    params: Mapping[str, Any],
    prm: GMSParameters,
    dc_gain: float | None,
    window: int,
    current_timing: str,
    v_min: float,
    reversal_skip: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """One run's (x, L, z, K, use): positions, the unscaled sliding level L = sgn(v) S(|v|),
    the target z = K (F_app - sigma2 v) - m a - K L, the kernel K and the usable samples."""
    t, x = signal(run, "time"), signal(run, "x")
    F_load, _ = run_load(run)
    force, a, v, K, _ = eq1_terms(
        t, x, current(run, dc_gain), params, params, F_load, window, current_timing
    )
    L = np.sign(v) * prm.level(v)
    z = apply_kernel(force - prm.viscous(v), K) - float(params["m"]) * a - apply_kernel(L, K)
    seg_id = np.concatenate(([0], np.cumsum(np.diff(np.sign(v)) != 0)))
    starts = np.concatenate(([0], np.flatnonzero(np.diff(seg_id)) + 1))
    travel = np.abs(x - x[starts][seg_id])
    bad = (np.abs(v) < v_min) | (travel < reversal_skip)
    # the filtered value at k sees samples k +- len(K)/2: keep that far from excluded ones
    bad = np.convolve(bad.astype(float), np.ones(len(K)), mode="same") > 0
    return x, L, z, K, ~bad & np.isfinite(z)


def identify_position_friction(
    runs: Sequence[Run],
    params: Mapping[str, Any],
    n_knots: int = N_KNOTS_MAX,
    dc_gain: float | None = None,
    window: int = 41,
    current_timing: str = "held",
    v_min: float = V_MIN,
    reversal_skip: float = REVERSAL_SKIP,
) -> PositionFrictionFit:
    """Fit p(x) on ``runs`` (module docstring) with every other parameter from ``params``
    (FMU names: maps, mass, friction levels with the switches applied; a profile already in
    ``params`` is ignored).

    Parameters
    ----------
    runs : constant-speed runs or slow sinusoids (columns time, x, i or u; F_load optional).
    n_knots : knots over the stroke the runs slid over (2..16).
    dc_gain : for runs without current, i = dc_gain u.
    window : Savitzky-Golay window of the acceleration [samples].
    """
    if not 2 <= n_knots <= N_KNOTS_MAX:
        raise ValueError(f"position friction: n_knots = {n_knots} outside 2..{N_KNOTS_MAX}")
    values = {**params, **structure_off(Structure.LEVEL_PROFILE)}  # the levels without p(x)
    prm = GMSParameters.from_params(values)
    rows = [
        _run_rows(r, values, prm, dc_gain, window, current_timing, v_min, reversal_skip)
        for r in runs
    ]
    xs = np.concatenate([x[use] for x, _, _, _, use in rows]) if rows else np.zeros(0)
    if xs.size < 10 * n_knots:
        raise ValueError(
            f"position friction: {xs.size} sliding samples (faster than "
            f"{v_min:g} m/s, {reversal_skip * 1e3:g} mm after reversals) in "
            f"{len(runs)} runs; need >= {10 * n_knots}"
        )
    lo, hi = float(xs.min()), float(xs.max())
    if hi - lo < 1e-3:
        raise ValueError(
            f"position friction: the runs slid over {1e3 * (hi - lo):.3g} mm "
            "only; a profile needs some stroke"
        )
    A_all, z_all = [], []
    for x, L, z, K, use in rows:
        B = profile_basis(x, lo, hi, n_knots) * L[:, None]
        A = np.column_stack([apply_kernel(B[:, j], K) for j in range(n_knots)])
        A_all.append(A[use])
        z_all.append(z[use])
    A, z = np.concatenate(A_all), np.concatenate(z_all)
    c, *_ = np.linalg.lstsq(A, z, rcond=1e-10)
    rms = float(np.sqrt(np.mean((z - A @ c) ** 2)))
    raw = FrictionProfile(lo, hi, tuple(float(v) for v in c))
    scale = float(np.median(raw(xs)))
    cn = np.clip((1.0 + c) / scale - 1.0, *C_RANGE)
    prof = FrictionProfile(lo, hi, tuple(float(v) for v in cn))
    out: dict[str, Any] = dict(prof.parameters())
    out["friction.F_s"] = float(params["friction.F_s"]) * scale
    out["friction.F_c"] = float(params["friction.F_c"]) * scale
    if is_on(owner(ASYMMETRY), params):  # the effect that owns the asymmetry is on
        out[ASYMMETRY] = float(params.get(ASYMMETRY, 0.0)) * scale
    return PositionFrictionFit(
        profile=prof,
        scale=scale,
        parameters=out,
        rms_residual=rms,
        n_used=int(xs.size),
        runs=[run_label(r) for r in runs],
    )
