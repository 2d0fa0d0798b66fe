"""Effect ``current_dynamics``: the current loop's dynamics G(z) of Eq. 2 (off: i = G(1) u)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from .candidate import CandidateContext, Variant
from .effect import Candidate, Effect, Identification, Parameter


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: the loop's G(z) in place of its DC gain, when the current
    is not measured but computed from u (the loop is then in the residual)."""
    m = ctx.model
    if m.effects["current_dynamics"]:
        return []
    if not all(
        q.i is not None and q.force_source.startswith("no current measured: i =") for q in ctx.res
    ):
        return []  # measured current, or F = gain * u: the loop is not in the residual
    loop = replace(ctx.plant.current, dynamics=True)

    def col(q: Any) -> np.ndarray:
        return ctx.plant.K_f(q.x) * (ctx.held_current(loop.current(q.u)) - q.i)

    Phi = -ctx.stack(col, mask_stuck=True)
    return [
        Variant(
            "current_dynamics",
            "G(z) of the model file instead of G(1)",
            Phi,
            ["scale"],
            to_model=lambda th: m.with_effect("current_dynamics", True),
        )
    ]


EFFECT = Effect(
    id="current_dynamics",
    switch="effects.current_dynamics",
    in_paper=True,
    description="current-loop dynamics G(z), Eq. 2",
    parameters=(
        Parameter("current.a[j]", "1", "sum(current.a) != 1 (a finite DC gain G(1))"),
        Parameter("current.b[j]", "A/V"),
    ),
    physics="feeddrive.physics.current_loop:CurrentLoop",
    identification=Identification(
        "current_loop",
        "feeddrive.identify.current_loop:identify_current_loop",
        "ARX fit of i against u on the PRBS run (order and delay chosen by the fit)",
    ),
    candidate=Candidate(
        "feeddrive.effects.current_dynamics:candidate",
        ("current.a[j]", "current.b[j]"),
        "G(z) of the model file instead of G(1)",
    ),
    report=(
        "current loop: order, delay, G(1) and fit percentage",
        "figure: PRBS response and identified G(z)",
    ),
)
