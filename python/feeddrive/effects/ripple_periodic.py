"""Effect ``ripple_periodic``: the Fourier part of the force constant K_f(x), Eq. 7."""

from __future__ import annotations

from .candidate import CandidateContext, Variant, periodic_variants
from .effect import Candidate, Effect, Identification, Parameter, ReportFigure


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: the ripple harmonics (times the current) corrected, extra
    wavelengths from the current-weighted spatial spectrum; none when a run has no current."""
    return periodic_variants(ctx, "ripple", "ripple_periodic", weighted=True)


EFFECT = Effect(
    id="ripple_periodic",
    switch="effects.ripple_periodic",
    in_paper=True,
    description="Fourier part of K_f(x), Eq. 7",
    parameters=(
        Parameter("ripple.lambda[j]", "m", "> 0 for a used harmonic slot"),
        Parameter("ripple.a[j]", "N/A"),
        Parameter("ripple.b[j]", "N/A"),
    ),
    physics="feeddrive.physics.position_maps:PositionMap",
    identification=Identification(
        "maps",
        "feeddrive.identify.position_maps:identify_position_maps",
        "DSTFT of K_f(x) sampled by constant-speed runs at two loads (Eqs. 3-5), harmonics fitted",
        label="position maps",
        order=2,
    ),
    candidate=Candidate(
        "feeddrive.effects.ripple_periodic:candidate",
        ("ripple.lambda[j]", "ripple.a[j]", "ripple.b[j]"),
        "harmonics at <wavelengths> mm (extra: <new wavelengths> mm)",
    ),
    report=("figures: DSTFT of K_f(x), its components, sampled and fitted K_f(x)",),
    position_map=("ripple", "periodic"),
    off=(("ripple.a[j]", 0.0), ("ripple.b[j]", 0.0)),
    figures=(
        ReportFigure(
            "feeddrive.report.identification_figures:fig8_dstft_ripple",
            "id_fig08_dstft_ripple",
            "Analogue of Fig. 8: DSTFT of K_f(x)",
            5,
        ),
        ReportFigure(
            "feeddrive.report.identification_figures:fig9_ripple_components",
            "id_fig09_ripple_components",
            "Analogue of Fig. 9: magnitude and unwrapped phase of X_K",
            6,
        ),
    ),
)
