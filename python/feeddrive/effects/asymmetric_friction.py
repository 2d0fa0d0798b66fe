"""Effect ``asymmetric_friction``: different Coulomb and viscous levels for v > 0 and v < 0."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .candidate import CandidateContext, Variant
from .effect import Candidate, Effect, Identification, Parameter


def check_levels(values: Mapping[str, Any], effective: Mapping[str, Any], on: bool) -> str | None:
    """With the asymmetry on, the friction level and the viscous coefficient for v < 0
    non-negative (friction_levels.c compile_asymmetric_friction; the levels for v > 0 with
    the other effects' switches applied): the FMU's message, else None."""
    if not on:
        return None
    Fc0 = float(values["friction.F_c"])
    Fs0 = float(effective["friction.F_s"])
    s0 = float(effective["friction.sigma2"])
    dF, ds = float(values["asymmetry.dF"]), float(values["asymmetry.dsigma2"])
    if Fc0 + dF < 0.0 or Fs0 + dF <= 0.0:
        return (
            f"asymmetry.dF = {dF:.17g} makes the friction level for v < 0 "
            f"negative: allowed [{-Fc0:.17g}, inf) N"
        )
    if s0 + ds < 0.0:
        return (
            f"asymmetry.dsigma2 = {ds:.17g} makes the viscous coefficient "
            f"for v < 0 negative: allowed [{-s0:.17g}, inf) N.s/m"
        )
    return None


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: a level shift and a viscous change for v < 0."""
    m = ctx.model
    on = m.effects["asymmetric_friction"]
    dF = float(m.parameters["asymmetry.dF"]) if on else 0.0
    ds = float(m.parameters["asymmetry.dsigma2"]) if on else 0.0
    # the level shift acts through the sliding elements only (stuck ones ignore it)
    frac = iter([ctx.sliding_fraction(q) for q in ctx.res])
    Phi = ctx.stack(
        lambda q: np.column_stack([-(q.v_f < 0).astype(float) * next(frac), q.v_f * (q.v_f < 0)]),
        mask_stuck=True,
    )
    return [
        Variant(
            "asymmetric_friction",
            "indicator(v<0), v*(v<0)",
            Phi,
            ["asymmetry.dF", "asymmetry.dsigma2"],
            refine=on,
            to_model=lambda th: m.with_effect(
                "asymmetric_friction",
                True,
                **{"asymmetry.dF": dF + th[0], "asymmetry.dsigma2": ds + th[1]},
            ),
        )
    ]


EFFECT = Effect(
    id="asymmetric_friction",
    switch="effects.asymmetric_friction",
    in_paper=False,
    description="different Coulomb/viscous levels for v > 0 and v < 0",
    parameters=(
        Parameter("asymmetry.dF", "N", "friction level for v < 0 stays >= 0"),
        Parameter("asymmetry.dsigma2", "N.s/m", "sigma2 + dsigma2 >= 0"),
    ),
    physics="feeddrive.physics.friction_gms:GMSParameters.level",
    identification=Identification(
        "",
        "",
        "no identification step; diagnosis fits asymmetry.dF and asymmetry.dsigma2 "
        "(the position_friction step scales asymmetry.dF with the level)",
    ),
    candidate=Candidate(
        "feeddrive.effects.asymmetric_friction:candidate",
        ("asymmetry.dF", "asymmetry.dsigma2"),
        "indicator(v<0), v*(v<0)",
    ),
    report=(),
    off=(("asymmetry.dF", 0.0), ("asymmetry.dsigma2", 0.0)),
    compile_rule=check_levels,
)
