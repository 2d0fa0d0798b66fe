"""Effect ``compliance``: a load m2 on a spring-damper attached to the slide (off: one rigid
moving mass)."""

from __future__ import annotations

from typing import Any

import numpy as np

from .candidate import SEARCH_STRIDE, CandidateContext, Variant
from .effect import Candidate, Effect, Identification, Parameter, Structure


def _start_columns(ctx: CandidateContext, f: float, zeta: float) -> np.ndarray:
    """Free responses of the load from each run's first valid sample, per run (the load's
    state there is not measured: ``load_free_response``; two columns per run, zero in the
    other runs' rows), stacked orthogonal to the run's GMS start."""
    index = {id(q): j for j, q in enumerate(ctx.res)}

    def cols(q: Any) -> np.ndarray:
        out = np.zeros((len(q.r), 2 * len(ctx.res)))
        j = index[id(q)]
        out[:, 2 * j : 2 * j + 2] = np.nan_to_num(ctx.load_free_response(q.a, q.Ts, f, zeta))
        return out

    return ctx.stack(cols, filtered=False)


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: a load m2 on a spring-damper: the residual gains m2 H(s) a
    (the load's inertial force), a = the (already filtered) measured acceleration.  (f, zeta)
    by the grid + Nelder-Mead of :func:`feeddrive.fits.compliance.fit_compliance`; variants:
    m2 alone, and m2 with a change of the slide's mass; both carry the load's free responses
    from each run's first valid sample (its state there is unknown) as nuisance columns.
    The residual's GMS start forces were estimated without the load: the search fits them
    again with it (their sensitivity as free columns), and every column is taken orthogonal
    to them (the context's ``stack``), or the start would keep part of the load's first
    oscillations and bias its damping.  At f -> inf the regressor is the mass's: the
    diagnosis ranks this family only when held-out data show it beyond the family it nests
    in (``Candidate.limit``)."""
    m = ctx.model
    on = m.effects["compliance"]
    P = ctx.plant.compliance
    if P.sensor_side != 0:
        return []  # the residual assumes the encoder on the slide
    base = None
    if on:
        base = ctx.stack(
            lambda q: P.m2 * ctx.load_acceleration(q.a, q.Ts, P.f, P.zeta), filtered=False
        )[:, 0]
    y = ctx.r + (base if base is not None else 0.0)
    starts = [
        q.start.full_basis(len(q.r)) if q.start is not None and q.start.basis is not None else None
        for q in ctx.res
    ]
    try:
        f, z = ctx.fit_compliance(ctx.unstack(y), SEARCH_STRIDE, starts)
    except ValueError:
        return []  # no acceleration to see a load by
    col = ctx.stack(lambda q: ctx.load_acceleration(q.a, q.Ts, f, z), filtered=False)
    acc = ctx.stack(lambda q: q.a, filtered=False)
    start = _start_columns(ctx, f, z)
    names = [f"load state at the start of {q.name} ({k})" for q in ctx.res for k in ("1", "2")]
    m_old = float(m.parameters["m"])
    upd = {"compliance.f": f, "compliance.zeta": z}
    label = f"f={f:.4g} Hz, zeta={z:.3g}"
    return [
        Variant(
            "compliance",
            label,
            np.column_stack([col, start]),
            ["compliance.m2"] + names,
            base=base,
            refine=on,
            nuisance=start.shape[1],
            to_model=lambda th: m.with_effect(
                "compliance", True, **{"compliance.m2": float(th[0]), **upd}
            ),
        ),
        Variant(
            "compliance",
            label + ", with a mass change",
            np.column_stack([col, acc, start]),
            ["compliance.m2", "m"] + names,
            base=base,
            refine=on,
            nuisance=start.shape[1],
            to_model=lambda th: m.with_effect(
                "compliance", True, m=m_old + float(th[1]), **{"compliance.m2": float(th[0]), **upd}
            ),
        ),
    ]


EFFECT = Effect(
    id="compliance",
    switch="effects.compliance",
    in_paper=False,
    description="a load m2 on a spring-damper attached to the slide",
    parameters=(
        Parameter("compliance.m2", "kg"),
        Parameter("compliance.f", "Hz"),
        Parameter("compliance.zeta", "1"),
        Parameter("compliance.sensor_side", "1", "0 (slide) or 1 (load)"),
    ),
    physics="feeddrive.physics.compliance:Compliance",
    identification=Identification(
        "",
        "feeddrive.identify.compliance:identify_compliance",
        "f, zeta, m2 from the rigid model's force residual (not a pipeline step)",
    ),
    candidate=Candidate(
        "feeddrive.effects.compliance:candidate",
        ("compliance.m2", "compliance.f", "compliance.zeta"),
        "f=<Hz>, zeta=<ratio>",
        limit=("m",),
    ),
    report=(),
    structure=Structure.LOAD_ON_SPRING,
)
