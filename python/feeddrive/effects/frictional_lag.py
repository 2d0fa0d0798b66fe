"""Effect ``frictional_lag``: a finite attraction C in the GMS slip phase, Eq. 11 (off: the
element forces follow nu_i s(v) at once)."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter

EFFECT = Effect(
    id="frictional_lag",
    switch="effects.frictional_lag",
    in_paper=True,
    description="finite attraction C in the slip phase, Eq. 11",
    parameters=(Parameter("friction.C", "N/s", "> 0"),),
    physics="feeddrive.physics.friction_gms:element_rates",
    identification=Identification(
        "attraction",
        "feeddrive.identify.attraction:identify_attraction",
        "Eq. 14's lag fitted to the friction of the variable-speed run",
    ),
    candidate=Candidate("feeddrive.diagnose.candidates:frictional_lag", ("friction.C",), "C=<N/s>"),
    report=("figure: frictional lag of the variable-speed run and Eq. 14 with the fitted C",),
    off=(("friction.C", float("inf")),),
)
