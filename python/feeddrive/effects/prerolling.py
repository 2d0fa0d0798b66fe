"""Effect ``prerolling``: the GMS's Maxwell-slip elements (elastic stick phase, hysteresis,
non-local memory); off: memoryless static friction, Eq. 12."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .effect import Candidate, Effect, Identification, Parameter, Structure, slot_count

#: |sum(nu_i) - 1| allowed over the elements in use (friction_gms.c SUM_NU_TOL).
SUM_NU_TOL = 1e-3


def check_elements(values: Mapping[str, Any], effective: Mapping[str, Any], on: bool) -> str | None:
    """friction.N an integer (on or off); with the elements on, friction.nu[1..N] summing to
    1 (friction_gms.c check_prerolling): the FMU's message, else None."""
    N = float(values["friction.N"])
    if int(N) != N:
        n_max = slot_count("friction.nu[j]", values)
        return f"friction.N = {N:.17g} is not an integer: allowed 1..{n_max}"
    if on:
        s = sum(float(values[f"friction.nu[{j}]"]) for j in range(1, int(N) + 1))
        if abs(s - 1.0) > SUM_NU_TOL:
            return (
                f"friction.nu[1..{int(N)}] sum to {s:.17g}: allowed 1 +- "
                f"{SUM_NU_TOL:g} (Eq. 12 needs sum(nu) = 1; set "
                f"friction.nu[{int(N)}] = 1 - sum of the others)"
            )
    return None


EFFECT = Effect(
    id="prerolling",
    switch="effects.prerolling",
    in_paper=True,
    description="GMS pre-rolling (elastic stick phase, hysteresis, non-local memory)",
    parameters=(
        Parameter("friction.N", "1", "an integer in 1..10"),
        Parameter("friction.nu[j]", "1", "friction.nu[1..N] sum to 1"),
        Parameter("friction.k[j]", "N/m"),
    ),
    physics="feeddrive.physics.friction_gms:gms_force",
    identification=Identification(
        "prerolling",
        "feeddrive.identify.prerolling:identify_prerolling",
        "weights W_i and travels Delta_i from two pre-rolling amplitudes (Eqs. 15-18)",
    ),
    candidate=Candidate(
        "feeddrive.diagnose.candidates:prerolling",
        ("friction.N", "friction.nu[j]", "friction.k[j]"),
        "Maxwell-slip, <n> elements, Delta <from>..<to> um",
    ),
    report=(
        "figures: GMS elements W_i against Delta_i, measured and modelled pre-rolling "
        "(Figs. 11, 13)",
    ),
    structure=Structure.SLIP_ELEMENTS,
    check_rule=check_elements,
    scenario="static friction instead of GMS",
)
