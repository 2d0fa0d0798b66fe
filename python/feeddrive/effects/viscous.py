"""Effect ``viscous``: the viscous term sigma2 v, Eq. 8 (off: sigma2 = 0)."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter

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
    candidate=Candidate("feeddrive.diagnose.candidates:viscous", ("friction.sigma2",), "v"),
    report=("truth table row friction.sigma2",),
    off=(("friction.sigma2", 0.0), ("asymmetry.dsigma2", 0.0)),
)
