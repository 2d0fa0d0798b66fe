"""Effect ``offset_force``: a constant force along the axis (tilt, cable, bellows preload)."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter

EFFECT = Effect(
    id="offset_force",
    switch="effects.offset_force",
    in_paper=False,
    description="constant force along the axis (tilt, cable, bellows preload)",
    parameters=(Parameter("offset.F", "N"),),
    physics="feeddrive.physics.plant:applied_force",
    identification=Identification(
        "", "", "no identification step (F_cg(x) absorbs a constant); diagnosis fits offset.F"
    ),
    candidate=Candidate("feeddrive.diagnose.candidates:offset_force", ("offset.F",), "constant"),
    report=(),
    off=(("offset.F", 0.0),),
)
