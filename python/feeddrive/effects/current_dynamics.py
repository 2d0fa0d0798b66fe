"""Effect ``current_dynamics``: the current loop's dynamics G(z) of Eq. 2 (off: i = G(1) u)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .effect import Candidate, Effect, Identification, Parameter, Structure

#: |1 - sum(current.a)| below which the current loop has a pole at z = 1.
POLE_TOL = 1e-9


def check_dc_gain(values: Mapping[str, Any], effective: Mapping[str, Any], on: bool) -> str | None:
    """sum(current.a) != 1, on or off (a finite DC gain G(1); current_loop.c
    compile_current_dynamics): the FMU's message, else None."""
    sa = sum(float(values[f"current.a[{j}]"]) for j in range(1, 6))
    if abs(1.0 - sa) < POLE_TOL:
        return (
            f"current.a[1..5] sum to {sa:.17g}: the current loop has a pole at "
            "z = 1 and no finite DC gain; allowed: sum(current.a) != 1"
        )
    return None


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
    compile_rule=check_dc_gain,
)
