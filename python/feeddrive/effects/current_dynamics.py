"""Effect ``current_dynamics``: the current loop's dynamics G(z) of Eq. 2 (off: i = G(1) u)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Any

import numpy as np

from .candidate import CandidateContext, Variant
from .effect import (
    Candidate,
    Effect,
    Experiment,
    Identification,
    Parameter,
    ReportFigure,
    Structure,
)

#: |1 - sum(current.a)| below which the current loop has a pole at z = 1.
POLE_TOL = 1e-9


def _unstable_order(a: list[float]) -> tuple[int, float]:
    """Schur-Cohn (step-down) test of the denominator z^n - a_1 z^(n-1) - ... - a_n of Eq. 2
    (current_loop.c): with alpha_i = -a_i the reflection coefficient of order j is
    k_j = alpha_j^(j), and alpha_i^(j-1) = (alpha_i - k_j alpha_(j-i)) / (1 - k_j^2); every root
    lies inside the unit circle iff |k_j| < 1 for j = n..1.  Returns (0, 0) when stable, else
    the order j whose |k_j| >= 1 and k_j."""
    al = [0.0] + [-x for x in a]
    for j in range(len(a), 0, -1):
        k = al[j]
        if not abs(k) < 1.0:
            return j, k
        al[1:j] = [(al[i] - k * al[j - i]) / (1.0 - k * k) for i in range(1, j)]
    return 0, 0.0


def check_dc_gain(values: Mapping[str, Any], effective: Mapping[str, Any], on: bool) -> str | None:
    """sum(current.a) != 1 and every pole of G(z) inside the unit circle, on or off (a finite
    DC gain G(1) of a stable loop; current_loop.c compile_current_dynamics): the FMU's
    message, else None."""
    a = [float(values[f"current.a[{j}]"]) for j in range(1, 6)]
    sa = sum(a)
    if abs(1.0 - sa) < POLE_TOL:
        return (
            f"current.a[1..5] sum to {sa:.17g}: the current loop has a pole at "
            "z = 1 and no finite DC gain; allowed: sum(current.a) != 1"
        )
    n = max((j for j in range(1, 6) if a[j - 1] != 0.0), default=0)
    bad, k = _unstable_order(a[:n])
    if bad:
        shown = ", ".join(f"{x:.9g}" for x in a)
        return (
            f"current.a[1..5] = {shown}: the current loop is unstable (a root of its "
            f"denominator z^n - a_1 z^(n-1) - ... - a_n, n = {n}, lies on or outside the unit "
            f"circle: Schur-Cohn reflection coefficient k_{bad} = {k:.9g}); allowed: every root "
            "inside |z| < 1 (all |k_j| < 1)"
        )
    return None


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: the loop's G(z) in place of its DC gain, when the current
    is not measured but computed from u (the loop is then in the residual)."""
    m = ctx.model
    if m.effects["current_dynamics"]:
        return []
    if not all(
        q.i is not None and q.force_source.startswith("no current measured: i =") for q in ctx.res
    ):
        return []  # measured current, or F = gain * u: the loop is not in the residual
    loop = replace(ctx.plant.current, dynamics=True)

    def col(q: Any) -> np.ndarray:
        return ctx.plant.K_f(q.x) * (ctx.held_current(loop.current(q.u)) - q.i)

    Phi = -ctx.stack(col, mask_stuck=True)
    return [
        Variant(
            "current_dynamics",
            "G(z) of the model file instead of G(1)",
            Phi,
            ["scale"],
            to_model=lambda th: m.with_effect("current_dynamics", True),
        )
    ]


EFFECT = Effect(
    id="current_dynamics",
    switch="effects.current_dynamics",
    in_paper=True,
    description="current-loop dynamics G(z), Eq. 2",
    parameters=(
        Parameter("current.a[j]", "1", "sum(current.a) != 1 and every pole of G(z) inside |z| < 1"),
        Parameter("current.b[j]", "A/V"),
    ),
    physics="feeddrive.physics.current_loop:CurrentLoop",
    identification=Identification(
        "current_loop",
        "feeddrive.identify.current_loop:identify_current_loop",
        "ARX fit of i against u on the PRBS run (order and delay chosen by the fit)",
        label="current loop",
        order=1,
        truth="feeddrive.identify.truth_table:current_loop_rows",
    ),
    candidate=Candidate(
        "feeddrive.effects.current_dynamics:candidate",
        ("current.a[j]", "current.b[j]"),
        "G(z) of the model file instead of G(1)",
    ),
    report=(
        "current loop: order, delay, G(1) and fit percentage",
        "figure: PRBS response and identified G(z)",
    ),
    structure=Structure.CURRENT_FILTER,
    compile_rule=check_dc_gain,
    experiments=(
        Experiment(
            group="prbs",
            kind="prbs",
            order=1,
            runs="feeddrive.experiments.prbs:prbs_runs",
            campaign="feeddrive.experiments.campaign:prbs_jobs",
            plan="feeddrive.experiments.plan:PlanBuilder.prbs",
            identifies="the current loop G(z): current.a, current.b (Eq. 2)",
            short="current loop",
            shape="held",
            file_pattern=r"prbs",
            uses="current loop (Eq. 2)",
        ),
    ),
    figures=(
        ReportFigure(
            "feeddrive.report.identification_figures:fig_current_loop",
            "id_current_loop",
            "Current loop: PRBS response and identified G(z)",
            1,
        ),
    ),
)
