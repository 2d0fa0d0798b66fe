"""Effect ``cogging_aperiodic``: the polynomial part of the cogging force F_cg(x), Eq. 6."""

from __future__ import annotations

import numpy as np

from .candidate import CandidateContext, Variant, poly_basis, polynomial_variant, span
from .effect import Candidate, Effect, Identification, Parameter, ReportFigure


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: a cubic in x over the stroke the runs visited."""
    m = ctx.model
    on = m.effects["cogging_aperiodic"]
    c, h = span(ctx)
    powers = range(4)
    Phi = ctx.stack(lambda q: poly_basis(q.x, c, h, powers), mask_stuck=True)
    old = (
        np.array([float(m.parameters[f"cogging.c[{k}]"]) for k in range(4)]) if on else np.zeros(4)
    )
    return [
        polynomial_variant(
            ctx,
            "cogging_aperiodic",
            "cogging",
            old,
            (c, h),
            Phi,
            "cubic in x",
            [f"xi^{k}" for k in powers],
        )
    ]


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
        label="position maps",
        order=2,
    ),
    candidate=Candidate(
        "feeddrive.effects.cogging_aperiodic:candidate", ("cogging.c[j]",), "cubic in x"
    ),
    report=("figure: sampled and fitted F_cg(x)",),
    position_map=("cogging", "aperiodic"),
    off=(("cogging.c[j]", 0.0),),
    scenario="without aperiodic cogging",
    figures=(
        ReportFigure(
            "feeddrive.report.identification_figures:fig5_maps",
            "id_fig05_maps",
            "Analogue of Fig. 5: force ripple K_f(x) and cogging F_cg(x)",
            2,
        ),
        ReportFigure(
            "feeddrive.report.identification_figures:fig10_map_fits",
            "id_fig10_map_fits",
            "Analogue of Fig. 10: sampled and fitted curves",
            7,
        ),
    ),
)
