"""Effect ``compliance``: a load m2 on a spring-damper attached to the slide (off: one rigid
moving mass)."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter, Structure

EFFECT = Effect(
    id="compliance",
    switch="effects.compliance",
    in_paper=False,
    description="a load m2 on a spring-damper attached to the slide",
    parameters=(
        Parameter("compliance.m2", "kg"),
        Parameter("compliance.f", "Hz"),
        Parameter("compliance.zeta", "1"),
        Parameter("compliance.sensor_side", "1", "0 (slide) or 1 (load)"),
    ),
    physics="feeddrive.physics.compliance:Compliance",
    identification=Identification(
        "",
        "feeddrive.identify.compliance:identify_compliance",
        "f, zeta, m2 from the rigid model's force residual (not a pipeline step)",
    ),
    candidate=Candidate(
        "feeddrive.diagnose.candidates:compliance",
        ("compliance.m2", "compliance.f", "compliance.zeta"),
        "f=<Hz>, zeta=<ratio>",
    ),
    report=(),
    structure=Structure.LOAD_ON_SPRING,
)
