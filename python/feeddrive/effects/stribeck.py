"""Effect ``stribeck``: the Stribeck drop F_s -> F_c with V_s and delta, Eq. 10 (off: F_s = F_c)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from scipy.optimize import minimize

from .candidate import CandidateContext, Variant, explained
from .effect import Candidate, Effect, Experiment, Identification, Parameter, ReportFigure


def check_levels(values: Mapping[str, Any], effective: Mapping[str, Any], on: bool) -> str | None:
    """friction.F_c <= friction.F_s, on or off (friction_levels.c compile_stribeck): the FMU's
    message, else None."""
    Fs, Fc = float(values["friction.F_s"]), float(values["friction.F_c"])
    if Fc > Fs:
        return (
            f"friction.F_c = {Fc:.17g} exceeds friction.F_s = {Fs:.17g}: "
            "allowed friction.F_c in [0, friction.F_s] N"
        )
    return None


#: Stribeck velocity [m/s] and exponent grid of the diagnosis candidate.
STRIBECK_VS = tuple(np.geomspace(3e-4, 3e-2, 11).tolist())
STRIBECK_DELTA = (0.4, 0.6, 1.0, 1.5, 2.0)
#: Stribeck grid points (best in-sample) kept as variants beside the refined one.
STRIBECK_KEEP = 3


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: the drop F_s - F_c times the sliding share and the drop's
    shape; (V_s, delta) by a grid, the best refined (Nelder-Mead), each a variant."""
    m = ctx.model
    p = m.parameters
    on = m.effects["stribeck"]
    frac = [ctx.sliding_fraction(q) for q in ctx.res]
    F_c = float(p["friction.F_c"])
    base = None
    if on:
        Vs0, d0, dS0 = (
            float(p["friction.V_s"]),
            float(p["friction.delta"]),
            float(p["friction.F_s"]) - F_c,
        )
        it = iter(frac)
        base = ctx.stack(lambda q: next(it) * dS0 * ctx.stribeck_drop(q.v_f, Vs0, d0))[:, 0]
    y = ctx.r + (base if base is not None else 0.0)

    def column(Vs: float, d: float) -> np.ndarray:
        it = iter(frac)
        return ctx.stack(lambda q: next(it) * ctx.stribeck_drop(q.v_f, Vs, d))

    # grid by in-sample explained energy (one column each), then a local refinement of the
    # best (log V_s, delta); the few best are scored on held-out blocks by the workflow
    grid = sorted(
        ((Vs, d) for Vs in STRIBECK_VS for d in STRIBECK_DELTA),
        key=lambda p: -explained(column(*p), y),
    )[:STRIBECK_KEEP]

    def neg(z: np.ndarray) -> float:
        return -explained(column(float(np.exp(z[0])), float(np.clip(z[1], 0.2, 3.0))), y)

    opt = minimize(
        neg,
        [np.log(grid[0][0]), grid[0][1]],
        method="Nelder-Mead",
        options={"xatol": 0.02, "fatol": 1e-6 * float(y @ y), "maxiter": 60},
    )
    refined = (float(np.exp(opt.x[0])), float(np.clip(opt.x[1], 0.2, 3.0)))
    out = []
    for Vs, d in [refined] + grid:

        def to_model(th: np.ndarray, Vs: float = Vs, d: float = d) -> Any:
            return m.with_effect(
                "stribeck",
                True,
                **{"friction.F_s": F_c + th[0], "friction.V_s": Vs, "friction.delta": d},
            )

        out.append(
            Variant(
                "stribeck",
                f"V_s={Vs * 1e3:.3g} mm/s, delta={d:.3g}",
                column(Vs, d),
                ["F_s - F_c"],
                base=base,
                refine=on,
                nonneg=True,
                to_model=to_model,
            )
        )
    return out


EFFECT = Effect(
    id="stribeck",
    switch="effects.stribeck",
    in_paper=True,
    description="Stribeck drop F_s → F_c with V_s, δ, Eq. 10",
    parameters=(
        Parameter("friction.F_s", "N"),
        Parameter("friction.F_c", "N", "friction.F_c in [0, friction.F_s]"),
        Parameter("friction.V_s", "m/s"),
        Parameter("friction.delta", "1"),
    ),
    physics="feeddrive.physics.friction_curves:stribeck_level",
    identification=Identification(
        "stribeck",
        "feeddrive.identify.stribeck:identify_stribeck",
        "Eq. 13's friction points of the constant-speed runs, Eq. 12 fitted (Fig. 12)",
        label="Stribeck",
        order=3,
        truth="feeddrive.identify.truth_table:stribeck_rows",
    ),
    candidate=Candidate(
        "feeddrive.effects.stribeck:candidate",
        ("friction.F_s", "friction.V_s", "friction.delta"),
        "V_s=<mm/s>, delta=<exponent>",
    ),
    report=(
        "figure: Eq. 13 points and the fitted Stribeck curve (Fig. 12)",
        "truth table rows friction.F_s, friction.F_c, friction.V_s, friction.delta",
    ),
    off=(("friction.F_s", "friction.F_c"),),
    compile_rule=check_levels,
    experiments=(
        Experiment(
            group="stribeck",
            kind="constant_speed",
            order=3,
            runs="feeddrive.experiments.constant_speed:stribeck_runs",
            campaign="feeddrive.experiments.campaign:stribeck_jobs",
            plan="feeddrive.experiments.plan:PlanBuilder.stribeck_runs",
            identifies="the Stribeck curve: friction.F_s, F_c, V_s, delta, sigma2 (Eqs. 12-13)",
            short="Stribeck curve",
            uses="Stribeck curve (Eqs. 12-13)",
        ),
    ),
    figures=(
        ReportFigure(
            "feeddrive.report.identification_figures:fig12_stribeck",
            "id_fig12_stribeck",
            "Analogue of Fig. 12: Stribeck points and fit",
            9,
        ),
    ),
)
