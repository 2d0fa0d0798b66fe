"""Effect ``viscous``: the viscous term sigma2 v, Eq. 8 (off: sigma2 = 0)."""

from __future__ import annotations

from .candidate import CandidateContext, Variant, one_column
from .effect import Candidate, Effect, Identification, Parameter


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: the friction velocity on the moving samples."""
    return one_column(ctx, "viscous", "v", "friction.sigma2", lambda q: q.v_f, mask_stuck=True)


EFFECT = Effect(
    id="viscous",
    switch="effects.viscous",
    in_paper=True,
    description="viscous term σ2·v, Eq. 8",
    parameters=(Parameter("friction.sigma2", "N.s/m"),),
    physics="feeddrive.physics.friction_gms:GMSParameters.viscous",
    identification=Identification(
        "",
        "feeddrive.identify.stribeck:identify_stribeck",
        "the slope of Eq. 12, fitted with the Stribeck curve to the constant-speed runs' "
        "friction points",
    ),
    candidate=Candidate(
        "feeddrive.effects.viscous:candidate", ("friction.sigma2",), "v", emps_baseline=True
    ),
    report=("truth table row friction.sigma2",),
    off=(("friction.sigma2", 0.0), ("asymmetry.dsigma2", 0.0)),
)
