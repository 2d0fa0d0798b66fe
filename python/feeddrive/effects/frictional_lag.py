"""Effect ``frictional_lag``: a finite attraction C in the GMS slip phase, Eq. 11 (off: the
element forces follow nu_i s(v) at once)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from scipy.optimize import minimize_scalar

from .candidate import CandidateContext, Variant, explained
from .effect import Candidate, Effect, Experiment, Identification, Parameter, ReportFigure
from .steps import IdentificationHost

#: Attraction parameter grid [N/s] of the diagnosis candidate (the best point is refined
#: between its neighbours).
LAG_C = tuple(np.geomspace(3.0, 3e5, 11).tolist())


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: the GMS friction with attraction C (a grid, the best refined)
    in place of the model's, one variant per C; none without GMS elements."""
    m = ctx.model
    if not ctx.plant.prerolling:
        return []  # slip-phase attraction only exists in the GMS
    on = m.effects["frictional_lag"]
    prm = ctx.plant.friction
    base = ctx.stack(lambda q: q.F_f - prm.viscous(q.v_f))[:, 0]
    y = ctx.r + base
    C_now = float(m.parameters["friction.C"]) if on else np.inf

    def column(C: float) -> np.ndarray:
        pc = replace(prm, C=C)
        return ctx.stack(
            lambda q: ctx.gms_force(q, pc, ctx.gms_start(q, len(pc.nu))) - pc.viscous(q.v_f)
        )

    cols = {C: column(C) for C in LAG_C if not (on and abs(np.log(C / C_now)) < 0.2)}
    if not cols:
        return []
    expl = {C: explained(A, y) for C, A in cols.items()}
    Cb = max(expl, key=lambda C: expl[C])
    # refine log C between the neighbours of the best grid point
    k = LAG_C.index(Cb)
    lo, hi = np.log(LAG_C[max(k - 1, 0)]), np.log(LAG_C[min(k + 1, len(LAG_C) - 1)])
    if hi > lo:
        opt = minimize_scalar(
            lambda z: -explained(column(float(np.exp(z))), y),
            bounds=(lo, hi),
            method="bounded",
            options={"xatol": 0.05, "maxiter": 8},
        )
        Cr = float(np.exp(opt.x))
        if -opt.fun > expl[Cb]:
            cols = {Cr: column(Cr), **cols}
    out = []
    for C, Phi in cols.items():

        def to_model(th: np.ndarray, C: float = C) -> Any:
            return m.with_effect("frictional_lag", True, **{"friction.C": C})

        out.append(
            Variant(
                "frictional_lag",
                f"C={C:.3g} N/s",
                Phi,
                ["scale"],
                base=base,
                refine=on,
                to_model=to_model,
            )
        )
    return out


def identify(host: IdentificationHost) -> Any:
    """The identification step: C (Eq. 14) from the longest variable-speed run; None when
    there is none."""
    ident, (exp,) = EFFECT.identification, EFFECT.experiments
    runs = host.runs(exp.kind)
    if not runs:
        host.skip(ident.label, "no variable-speed run")
        return None
    run = max(runs, key=lambda r: len(r.time))
    fit = host.fit(
        ident.label,
        ident.fit,
        run,
        host.params,
        dc_gain=host.dc_gain,
        current_timing=host.current_timing,
    )
    host.take(fit.parameters)
    return fit


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
        label="attraction",
        order=5,
        run=identify,
        truth="feeddrive.identify.truth_table:attraction_rows",
    ),
    candidate=Candidate("feeddrive.effects.frictional_lag:candidate", ("friction.C",), "C=<N/s>"),
    report=("figure: frictional lag of the variable-speed run and Eq. 14 with the fitted C",),
    off=(("friction.C", float("inf")),),
    experiments=(
        Experiment(
            group="variable_speed",
            kind="variable_speed",
            order=5,
            runs="feeddrive.experiments.variable_speed:variable_speed_runs",
            campaign="feeddrive.experiments.campaign:variable_speed_jobs",
            plan="feeddrive.experiments.plan:PlanBuilder.variable_speed",
            identifies="the GMS attraction parameter friction.C (Eq. 14)",
            short="C",
            shape="varying",
            file_pattern=r"variable_speed",
            uses="attraction parameter C (Eq. 14)",
        ),
    ),
    figures=(
        ReportFigure(
            "feeddrive.report.identification_figures:fig_attraction",
            "id_attraction",
            "Attraction parameter C: frictional lag",
            10,
        ),
    ),
)
