"""Effect ``mass``: the moving mass m of Eq. 1 (always on; a wrong value is a missing effect)."""

from __future__ import annotations

from typing import Any

from .candidate import CandidateContext, Variant, one_column
from .effect import Candidate, Effect, Experiment, Identification, Parameter
from .steps import IdentificationHost


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: a change of the mass, the (unfiltered) acceleration."""
    return one_column(ctx, "mass", "acceleration", "m", lambda q: q.a, filtered=False)


def identify(host: IdentificationHost) -> Any:
    """The identification step: m from the open-loop force run (Eq. 1), the maps and
    friction of the steps before it known; None when there is no such run."""
    ident, (exp,) = EFFECT.identification, EFFECT.experiments
    runs = host.runs(exp.kind)
    if not runs:
        host.skip(ident.label, "no open-loop force run")
        return None
    p = host.params
    fit = host.fit(
        ident.label,
        ident.fit,
        runs[0],
        p,
        p,
        friction=p,
        dc_gain=host.dc_gain,
        current_timing=host.current_timing,
    )
    host.take({"m": fit.parameters["m"]})
    return fit


EFFECT = Effect(
    id="mass",
    switch=None,
    in_paper=True,
    description="moving mass m (a wrong value is a missing effect too)",
    parameters=(Parameter("m", "kg", "> 0"),),
    physics="feeddrive.physics.plant:force_residual",
    identification=Identification(
        "mass",
        "feeddrive.identify.mass:identify_mass",
        "Eq. 1 fitted to the open-loop force run",
        label="mass",
        order=4,
        run=identify,
        truth="feeddrive.identify.truth_table:mass_rows",
    ),
    candidate=Candidate(
        "feeddrive.effects.mass:candidate", ("m",), "acceleration", emps_baseline=True
    ),
    report=("truth table row m",),
    experiments=(
        Experiment(
            group="force_open_loop",
            kind="force_open_loop",
            order=4,
            runs="feeddrive.experiments.force_open_loop:force_open_loop_runs",
            campaign="feeddrive.experiments.campaign:force_open_loop_jobs",
            plan="feeddrive.experiments.plan:PlanBuilder.force_open_loop",
            identifies="the moving mass m (Eq. 1)",
            short="mass",
            shape="open_loop",
            file_pattern=r"force_open_loop|open_loop",
            uses="mass (Eq. 1)",
        ),
    ),
)
