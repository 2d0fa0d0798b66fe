"""Effect ``cogging_periodic``: the Fourier part of the cogging force F_cg(x), Eq. 6."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .candidate import CandidateContext, Variant, periodic_variants
from .effect import Candidate, Effect, Experiment, Identification, Parameter, ReportFigure


def check_stroke(values: Mapping[str, Any], effective: Mapping[str, Any], on: bool) -> str | None:
    """stroke.x_max > stroke.x_min, the interval the position maps are clamped to (checked by
    the first map entry of position_maps.c): the FMU's message, else None."""
    x0, x1 = float(values["stroke.x_min"]), float(values["stroke.x_max"])
    if not x1 > x0:
        return (
            f"stroke.x_max = {x1:.17g} must exceed stroke.x_min = {x0:.17g}: "
            f"allowed stroke.x_max in ({x0:.17g}, inf) m"
        )
    return None


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: the cogging harmonics corrected, extra wavelengths from the
    residual's spatial spectrum."""
    return periodic_variants(ctx, "cogging", "cogging_periodic", weighted=False)


EFFECT = Effect(
    id="cogging_periodic",
    switch="effects.cogging_periodic",
    in_paper=True,
    description="Fourier part of F_cg(x) (magnet-pitch harmonics), Eq. 6",
    parameters=(
        Parameter("cogging.lambda[j]", "m", "> 0 for a used harmonic slot"),
        Parameter("cogging.a[j]", "N"),
        Parameter("cogging.b[j]", "N"),
    ),
    physics="feeddrive.physics.position_maps:PositionMap",
    identification=Identification(
        "maps",
        "feeddrive.identify.position_maps:identify_position_maps",
        "DSTFT of F_cg(x) sampled by the constant-speed runs (Eqs. 3-5), harmonics fitted",
        label="position maps",
        order=2,
        truth="feeddrive.identify.truth_table:map_rows",
    ),
    candidate=Candidate(
        "feeddrive.effects.cogging_periodic:candidate",
        ("cogging.lambda[j]", "cogging.a[j]", "cogging.b[j]"),
        "harmonics at <wavelengths> mm (extra: <new wavelengths> mm)",
    ),
    report=("figures: DSTFT of F_cg(x), its components, sampled and fitted F_cg(x)",),
    position_map=("cogging", "periodic"),
    off=(("cogging.a[j]", 0.0), ("cogging.b[j]", 0.0)),
    compile_rule=check_stroke,
    experiments=(
        Experiment(
            group="cogging_ripple",
            kind="constant_speed",
            order=2,
            runs="feeddrive.experiments.constant_speed:constant_speed_runs",
            campaign="feeddrive.experiments.campaign:map_jobs",
            plan="feeddrive.experiments.plan:PlanBuilder.map_runs",
            identifies="force ripple K_f(x) and cogging F_cg(x): ripple.*, cogging.* (Eqs. 3-7)",
            short="K_f(x), F_cg(x)",
            plan_group="maps",
            shape="steady",
            file_pattern=r"cv_|constant_speed",
            uses="K_f, F_cg (Eqs. 3-7)",
        ),
    ),
    figures=(
        ReportFigure(
            "feeddrive.report.identification_figures:fig6_dstft_cogging",
            "id_fig06_dstft_cogging",
            "Analogue of Fig. 6: DSTFT of F_cg(x)",
            3,
        ),
        ReportFigure(
            "feeddrive.report.identification_figures:fig7_cogging_components",
            "id_fig07_cogging_components",
            "Analogue of Fig. 7: magnitude and unwrapped phase of X_F",
            4,
        ),
    ),
)
