"""Effect ``cogging_aperiodic``: the polynomial part of the cogging force F_cg(x), Eq. 6."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter

EFFECT = Effect(
    id="cogging_aperiodic",
    switch="effects.cogging_aperiodic",
    in_paper=True,
    description="polynomial part of F_cg(x), Eq. 6",
    parameters=(Parameter("cogging.c[j]", "N/m^j"),),
    physics="feeddrive.physics.position_maps:PositionMap",
    identification=Identification(
        "maps",
        "feeddrive.identify.position_maps:identify_position_maps",
        "cubic fitted to F_cg(x) sampled by the constant-speed runs (Eqs. 3-6)",
    ),
    candidate=Candidate(
        "feeddrive.diagnose.candidates:cogging_aperiodic", ("cogging.c[j]",), "cubic in x"
    ),
    report=("figure: sampled and fitted F_cg(x)",),
    position_map=("cogging", "aperiodic"),
    off=(("cogging.c[j]", 0.0),),
    scenario="without aperiodic cogging",
)
