"""Effect ``asymmetric_friction``: different Coulomb and viscous levels for v > 0 and v < 0."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter

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
        "feeddrive.diagnose.candidates:asymmetric_friction",
        ("asymmetry.dF", "asymmetry.dsigma2"),
        "indicator(v<0), v*(v<0)",
    ),
    report=(),
    off=(("asymmetry.dF", 0.0), ("asymmetry.dsigma2", 0.0)),
)
