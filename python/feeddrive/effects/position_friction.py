"""Effect ``position_friction``: the friction level varying along the stroke, a profile p(x)
scaling F_s and F_c (guideway wear, lubrication, preload)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .candidate import CandidateContext, Variant
from .effect import Candidate, Effect, Identification, Parameter, Structure, slot_count
from .steps import IdentificationHost


def check_profile(values: Mapping[str, Any], effective: Mapping[str, Any], on: bool) -> str | None:
    """friction_profile.x_end > friction_profile.x_start and friction_profile.n an integer,
    on or off (friction_position.c check_position_friction): the FMU's message, else None."""
    p0, p1 = float(values["friction_profile.x_start"]), float(values["friction_profile.x_end"])
    if not p1 > p0:
        return (
            f"friction_profile.x_end = {p1:.17g} must exceed "
            f"friction_profile.x_start = {p0:.17g}: allowed "
            f"friction_profile.x_end in ({p0:.17g}, inf) m"
        )
    n = float(values["friction_profile.n"])
    if int(n) != n:
        n_max = slot_count("friction_profile.c[j]", values)
        return f"friction_profile.n = {n:.17g} is not an integer: allowed 2..{n_max}"
    return None


#: Knot counts of the diagnosis candidate over the stroke the runs visited (the FMU holds up
#: to 16); each is a variant, the parsimony rule prefers fewer knots.
PROFILE_KNOTS = (4, 7, 10, 13, 16)


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: p(x) = 1 + sum_j c_j B_j(x): regressors B_j(x) times the
    sliding friction, filtered like the residual, uniform knots over the stroke the runs
    visited, one variant per count of ``PROFILE_KNOTS``.  With the effect on (a refinement)
    the model's own knots are corrected (c + dc), and each grid of the visited stroke is
    offered too, fitted in place of the model's profile (its contribution is the variant's
    ``base``): the polish after a first step can so move to finer knots than the held-out
    choice."""
    m = ctx.model
    on = m.effects["position_friction"]
    x = ctx.all("x")
    lo, hi = float(x.min()), float(x.max())
    grids: list[tuple[float, float, int, np.ndarray | None]] = []
    base = None
    if on:
        prof = ctx.model_profile()
        grids.append((prof.x_start, prof.x_end, prof.n, np.asarray(prof.c)))
        base = ctx.stack(lambda q: (prof(q.x) - 1.0) * ctx.sliding_level(q), mask_stuck=True)[:, 0]
    if hi - lo >= 1e-3:  # else no stroke to tell a profile from a level
        grids += [(lo, hi, n, None) for n in PROFILE_KNOTS]
    out = []
    for x0, x1, n, old in grids:

        def basis(q: Any, x0: float = x0, x1: float = x1, n: int = n) -> np.ndarray:
            return ctx.profile_basis(q.x, x0, x1, n) * ctx.sliding_level(q)[:, None]

        Phi = ctx.stack(basis, mask_stuck=True)

        def to_model(
            th: np.ndarray, x0: float = x0, x1: float = x1, old: np.ndarray | None = old
        ) -> Any:
            c = (old if old is not None else 0.0) + np.asarray(th, dtype=float)
            return m.with_effect(
                "position_friction", True, **ctx.friction_profile(x0, x1, c).parameters()
            )

        label = f"{n} knots over {x0 * 1e3:.1f}-{x1 * 1e3:.1f} mm"
        out.append(
            Variant(
                "position_friction",
                label + (" (new grid)" if on and old is None else ""),
                Phi,
                [f"c[{j + 1}]" for j in range(n)],
                refine=on,
                base=base if on and old is None else None,
                to_model=to_model,
            )
        )
    return out


def identify(host: IdentificationHost) -> Any:
    """The identification step (on request): p(x) from every constant-speed run, the levels
    and maps identified so far; None when there is none."""
    ident = EFFECT.identification
    runs = host.runs("constant_speed")
    if not runs:
        host.skip(ident.label, "no constant-speed runs")
        return None
    fit = host.fit(
        ident.label,
        ident.fit,
        runs,
        host.params,
        n_knots=host.profile_knots,
        dc_gain=host.dc_gain,
        current_timing=host.current_timing,
    )
    host.take(fit.parameters)
    return fit


EFFECT = Effect(
    id="position_friction",
    switch="effects.position_friction",
    in_paper=False,
    description="friction level varying along the stroke, p(x) scaling F_s and F_c",
    parameters=(
        Parameter("friction_profile.x_start", "m"),
        Parameter("friction_profile.x_end", "m", "> friction_profile.x_start"),
        Parameter("friction_profile.n", "1", "an integer in 2..16"),
        Parameter("friction_profile.c[j]", "1"),
    ),
    physics="feeddrive.physics.friction_position:FrictionProfile",
    identification=Identification(
        "position_friction",
        "feeddrive.identify.position_friction:identify_position_friction",
        "p(x) from the constant-speed runs' friction along the stroke (identify "
        "--position-friction)",
        label="position friction",
        order=7,
        run=identify,
        on_request=True,
        truth="feeddrive.identify.truth_table:profile_rows",
    ),
    candidate=Candidate(
        "feeddrive.effects.position_friction:candidate",
        (
            "friction_profile.x_start",
            "friction_profile.x_end",
            "friction_profile.n",
            "friction_profile.c[j]",
        ),
        "<n> knots over <from>-<to> mm",
    ),
    report=("truth table rows friction_profile.c[j]",),
    structure=Structure.LEVEL_PROFILE,
    check_rule=check_profile,
)
