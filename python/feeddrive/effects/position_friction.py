"""Effect ``position_friction``: the friction level varying along the stroke, a profile p(x)
scaling F_s and F_c (guideway wear, lubrication, preload)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .effect import Candidate, Effect, Identification, Parameter, Structure, slot_count


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
    structure=Structure.LEVEL_PROFILE,
    check_rule=check_profile,
)
