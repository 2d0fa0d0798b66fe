"""Effect ``ripple_aperiodic``: the polynomial part of K_f(x) beyond its constant, Eq. 7."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter

EFFECT = Effect(
    id="ripple_aperiodic",
    switch="effects.ripple_aperiodic",
    in_paper=True,
    description="polynomial part of K_f(x) beyond its constant term, Eq. 7",
    parameters=(Parameter("ripple.c[j]", "N/(A.m^j)", "ripple.c[0] stays when off (K_f = c0)"),),
    physics="feeddrive.physics.position_maps:PositionMap",
    identification=Identification(
        "maps",
        "feeddrive.identify.position_maps:identify_position_maps",
        "quadratic fitted to K_f(x) sampled by constant-speed runs at two loads (Eqs. 3-7)",
    ),
    candidate=Candidate(
        "feeddrive.diagnose.candidates:ripple_aperiodic", ("ripple.c[j]",), "i * (1, x, x^2)"
    ),
    report=("figure: sampled and fitted K_f(x)",),
    position_map=("ripple", "aperiodic"),
    off=(("ripple.c[1]", 0.0), ("ripple.c[2]", 0.0)),
)
