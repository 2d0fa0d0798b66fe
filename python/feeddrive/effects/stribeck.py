"""Effect ``stribeck``: the Stribeck drop F_s -> F_c with V_s and delta, Eq. 10 (off: F_s = F_c)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .effect import Candidate, Effect, Identification, Parameter


def check_levels(values: Mapping[str, Any], effective: Mapping[str, Any], on: bool) -> str | None:
    """friction.F_c <= friction.F_s, on or off (friction_levels.c compile_stribeck): the FMU's
    message, else None."""
    Fs, Fc = float(values["friction.F_s"]), float(values["friction.F_c"])
    if Fc > Fs:
        return (
            f"friction.F_c = {Fc:.17g} exceeds friction.F_s = {Fs:.17g}: "
            "allowed friction.F_c in [0, friction.F_s] N"
        )
    return None


EFFECT = Effect(
    id="stribeck",
    switch="effects.stribeck",
    in_paper=True,
    description="Stribeck drop F_s → F_c with V_s, δ, Eq. 10",
    parameters=(
        Parameter("friction.F_s", "N"),
        Parameter("friction.F_c", "N", "friction.F_c in [0, friction.F_s]"),
        Parameter("friction.V_s", "m/s"),
        Parameter("friction.delta", "1"),
    ),
    physics="feeddrive.physics.friction_curves:stribeck_level",
    identification=Identification(
        "stribeck",
        "feeddrive.identify.stribeck:identify_stribeck",
        "Eq. 13's friction points of the constant-speed runs, Eq. 12 fitted (Fig. 12)",
    ),
    candidate=Candidate(
        "feeddrive.diagnose.candidates:stribeck",
        ("friction.F_s", "friction.V_s", "friction.delta"),
        "V_s=<mm/s>, delta=<exponent>",
    ),
    report=(
        "figure: Eq. 13 points and the fitted Stribeck curve (Fig. 12)",
        "truth table rows friction.F_s, friction.F_c, friction.V_s, friction.delta",
    ),
    off=(("friction.F_s", "friction.F_c"),),
    compile_rule=check_levels,
)
