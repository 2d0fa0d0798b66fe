"""Effect ``ripple_aperiodic``: the polynomial part of K_f(x) beyond its constant, Eq. 7."""

from __future__ import annotations

from typing import Any

import numpy as np

from .candidate import CandidateContext, Variant, poly_basis, polynomial_variant, span
from .effect import Candidate, Effect, Identification, Parameter


def _current(q: Any) -> np.ndarray:
    """The run's current (the candidate is offered only when every run has one)."""
    if q.i is None:
        raise ValueError(f"{q.name}: no current")
    return q.i


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: the current times a quadratic in x (a change of K_f(x));
    none when a run has no current."""
    m = ctx.model
    if any(q.i is None for q in ctx.res):
        return []  # F = gain * u: no K_f(x) to refine
    on = m.effects["ripple_aperiodic"]
    c, h = span(ctx)
    # the constant is included: with the polynomial off the model's K_f is c0 alone, and the
    # truth's drift over a short stretch of stroke is mostly a change of level (which trades
    # off with the mass only when friction and cogging leave i proportional to a)
    powers = range(3)
    # more K_f means more motor force: r = -(dK_f) i
    Phi = -ctx.stack(
        lambda q: _current(q)[:, None] * poly_basis(q.x, c, h, powers), mask_stuck=True
    )
    old = np.array([float(m.parameters[f"ripple.c[{k}]"]) for k in range(3)])
    if not on:
        old[1:] = 0.0  # off: K_f = c0 on the stroke
    return [
        polynomial_variant(
            ctx,
            "ripple_aperiodic",
            "ripple",
            old,
            (c, h),
            Phi,
            "i * (1, x, x^2)",
            ["i", "i*xi", "i*xi^2"],
        )
    ]


EFFECT = Effect(
    id="ripple_aperiodic",
    switch="effects.ripple_aperiodic",
    in_paper=True,
    description="polynomial part of K_f(x) beyond its constant term, Eq. 7",
    parameters=(Parameter("ripple.c[j]", "N/(A.m^j)", "ripple.c[0] stays when off (K_f = c0)"),),
    physics="feeddrive.physics.position_maps:PositionMap",
    identification=Identification(
        "maps",
        "feeddrive.identify.position_maps:identify_position_maps",
        "quadratic fitted to K_f(x) sampled by constant-speed runs at two loads (Eqs. 3-7)",
        label="position maps",
        order=2,
    ),
    candidate=Candidate(
        "feeddrive.effects.ripple_aperiodic:candidate", ("ripple.c[j]",), "i * (1, x, x^2)"
    ),
    report=("figure: sampled and fitted K_f(x)",),
    position_map=("ripple", "aperiodic"),
    off=(("ripple.c[1]", 0.0), ("ripple.c[2]", 0.0)),
)
