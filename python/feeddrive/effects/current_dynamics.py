"""Effect ``current_dynamics``: the current loop's dynamics G(z) of Eq. 2 (off: i = G(1) u)."""

from __future__ import annotations

from .effect import Candidate, Effect, Identification, Parameter, Structure

EFFECT = Effect(
    id="current_dynamics",
    switch="effects.current_dynamics",
    in_paper=True,
    description="current-loop dynamics G(z), Eq. 2",
    parameters=(
        Parameter("current.a[j]", "1", "sum(current.a) != 1 (a finite DC gain G(1))"),
        Parameter("current.b[j]", "A/V"),
    ),
    physics="feeddrive.physics.current_loop:CurrentLoop",
    identification=Identification(
        "current_loop",
        "feeddrive.identify.current_loop:identify_current_loop",
        "ARX fit of i against u on the PRBS run (order and delay chosen by the fit)",
    ),
    candidate=Candidate(
        "feeddrive.diagnose.candidates:current_dynamics",
        ("current.a[j]", "current.b[j]"),
        "G(z) of the model file instead of G(1)",
    ),
    report=(
        "current loop: order, delay, G(1) and fit percentage",
        "figure: PRBS response and identified G(z)",
    ),
    structure=Structure.CURRENT_FILTER,
)
