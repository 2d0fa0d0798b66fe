"""Effect ``position_friction``: the friction level varying along the stroke, a profile p(x)
scaling F_s and F_c (guideway wear, lubrication, preload)."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter

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
    ),
    candidate=Candidate(
        "feeddrive.diagnose.candidates:position_friction",
        (
            "friction_profile.x_start",
            "friction_profile.x_end",
            "friction_profile.n",
            "friction_profile.c[j]",
        ),
        "<n> knots over <from>-<to> mm",
    ),
    report=("truth table rows friction_profile.c[j]",),
)
