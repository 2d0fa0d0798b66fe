"""Effect ``offset_force``: a constant force along the axis (tilt, cable, bellows preload)."""

from __future__ import annotations

import numpy as np

from .candidate import CandidateContext, Variant, one_column
from .effect import Candidate, Effect, Identification, Parameter


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: a constant force on the moving samples."""
    return one_column(
        ctx, "offset_force", "constant", "offset.F", lambda q: np.ones(len(q.r)), mask_stuck=True
    )


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
    candidate=Candidate(
        "feeddrive.effects.offset_force:candidate",
        ("offset.F",),
        "constant",
        emps_baseline=True,
    ),
    report=(),
    off=(("offset.F", 0.0),),
)
