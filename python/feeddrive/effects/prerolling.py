"""Effect ``prerolling``: the GMS's Maxwell-slip elements (elastic stick phase, hysteresis,
non-local memory); off: memoryless static friction, Eq. 12."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter

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
)
