"""Effect ``mass``: the moving mass m of Eq. 1 (always on; a wrong value is a missing effect)."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter

EFFECT = Effect(
    id="mass",
    switch=None,
    in_paper=True,
    description="moving mass m (a wrong value is a missing effect too)",
    parameters=(Parameter("m", "kg", "> 0"),),
    physics="feeddrive.physics.plant:force_residual",
    identification=Identification(
        "mass", "feeddrive.identify.mass:identify_mass", "Eq. 1 fitted to the open-loop force run"
    ),
    candidate=Candidate("feeddrive.diagnose.candidates:mass", ("m",), "acceleration"),
    report=("truth table row m",),
)
