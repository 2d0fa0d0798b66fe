"""Effect ``prerolling``: the GMS's Maxwell-slip elements (elastic stick phase, hysteresis,
non-local memory); off: memoryless static friction, Eq. 12."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
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
    slot_count,
)
from .steps import IdentificationHost

#: |sum(nu_i) - 1| allowed over the elements in use (friction_gms.c SUM_NU_TOL).
SUM_NU_TOL = 1e-3


def check_elements(values: Mapping[str, Any], effective: Mapping[str, Any], on: bool) -> str | None:
    """friction.N an integer (on or off); with the elements on, friction.nu[1..N] summing to
    1 (friction_gms.c check_prerolling): the FMU's message, else None."""
    N = float(values["friction.N"])
    if int(N) != N:
        n_max = slot_count("friction.nu[j]", values)
        return f"friction.N = {N:.17g} is not an integer: allowed 1..{n_max}"
    if on:
        s = sum(float(values[f"friction.nu[{j}]"]) for j in range(1, int(N) + 1))
        if abs(s - 1.0) > SUM_NU_TOL:
            return (
                f"friction.nu[1..{int(N)}] sum to {s:.17g}: allowed 1 +- "
                f"{SUM_NU_TOL:g} (Eq. 12 needs sum(nu) = 1; set "
                f"friction.nu[{int(N)}] = 1 - sum of the others)"
            )
    return None


#: Maxwell-slip element travels tried by the diagnosis candidate [m].
PREROLL_DELTAS = tuple(np.geomspace(2e-6, 300e-6, 8).tolist())


def _gms_unit_columns(ctx: CandidateContext, q: Any, deltas: Sequence[float]) -> np.ndarray:
    """Friction of one Maxwell-slip element (nu = 1, travel Delta) per Delta, no viscous;
    each starts holding the friction the residual's model held at the first sample (the
    run's estimated start, clipped to the element's level), virgin without one."""
    prm = ctx.plant.friction
    held = float(np.sum(q.start.F0)) if q.start is not None else 0.0
    cols = []
    for D in deltas:
        pe = replace(prm, nu=(1.0,), k=(prm.F_s / D,), sigma2=0.0, dsigma2=0.0)
        F0 = [float(np.clip(held, -(prm.F_s + prm.dF), prm.F_s))]
        cols.append(ctx.gms_force(q, pe, F0))
    return np.column_stack(cols)


def candidate(ctx: CandidateContext) -> list[Variant]:
    """The diagnosis candidate: one Maxwell-slip element per travel of ``PREROLL_DELTAS``,
    weights non-negative and summing to one, in place of the model's friction."""
    m = ctx.model
    on = m.effects["prerolling"]
    prm = ctx.plant.friction
    deltas = PREROLL_DELTAS
    n_max = ctx.n_elements_max
    Phi = ctx.stack(lambda q: _gms_unit_columns(ctx, q, deltas))
    base = ctx.stack(lambda q: q.F_f - prm.viscous(q.v_f))[:, 0]
    F_s = prm.F_s

    def to_model(th: np.ndarray) -> Any:
        th = np.clip(th, 0.0, None)
        keep = np.flatnonzero(th > 1e-3 * th.max())[:n_max]
        nu = th[keep] / th[keep].sum()
        kk = nu * F_s / np.asarray(deltas)[keep]
        upd: dict[str, float | int] = {"friction.N": int(len(keep))}
        for j in range(n_max):
            upd[f"friction.nu[{j + 1}]"] = float(nu[j]) if j < len(keep) else 0.0
            upd[f"friction.k[{j + 1}]"] = float(kk[j]) if j < len(keep) else 1.0e5
        return m.with_effect("prerolling", True, **upd)

    return [
        Variant(
            "prerolling",
            f"Maxwell-slip, {len(deltas)} elements, "
            f"Delta {deltas[0] * 1e6:.3g}..{deltas[-1] * 1e6:.3g} um",
            Phi,
            [f"W/F_s at Delta={D * 1e6:.3g} um" for D in deltas],
            base=base,
            nonneg=True,
            sum_to_one=True,
            refine=on,
            to_model=to_model,
        )
    ]


def identify(host: IdentificationHost) -> Any:
    """The identification step: the Maxwell-slip elements from the largest and smallest
    periodic runs (Eqs. 15-18); None with fewer than two."""
    ident, (exp,) = EFFECT.identification, EFFECT.experiments
    pr = sorted(host.runs(exp.kind), key=lambda r: np.ptp(r.x))
    if len(pr) < 2:
        host.skip(ident.label, f"{len(pr)} periodic runs (a small and a large amplitude needed)")
        return None
    fit = host.fit(
        ident.label,
        ident.fit,
        pr[-1],
        pr[0],
        host.params,
        N=host.prerolling_elements,
        current_timing=host.current_timing,
        dc_gain=host.dc_gain,
    )
    host.take(fit.parameters)
    if len(pr) > 2:
        host.note(f"{ident.label}: used the smallest and largest of {len(pr)} runs")
    return fit


EFFECT = Effect(
    id="prerolling",
    switch="effects.prerolling",
    in_paper=True,
    description="GMS pre-rolling (elastic stick phase, hysteresis, non-local memory)",
    parameters=(
        Parameter("friction.N", "1", "an integer in 1..10"),
        Parameter("friction.nu[j]", "1", "friction.nu[1..N] sum to 1"),
        Parameter("friction.k[j]", "N/m"),
    ),
    physics="feeddrive.physics.friction_gms:gms_force",
    identification=Identification(
        "prerolling",
        "feeddrive.identify.prerolling:identify_prerolling",
        "weights W_i and travels Delta_i from two pre-rolling amplitudes (Eqs. 15-18)",
        label="pre-rolling",
        order=6,
        run=identify,
        truth="feeddrive.identify.truth_table:prerolling_rows",
    ),
    candidate=Candidate(
        "feeddrive.effects.prerolling:candidate",
        ("friction.N", "friction.nu[j]", "friction.k[j]"),
        "Maxwell-slip, <n> elements, Delta <from>..<to> um",
    ),
    report=(
        "figures: GMS elements W_i against Delta_i, measured and modelled pre-rolling "
        "(Figs. 11, 13)",
    ),
    structure=Structure.SLIP_ELEMENTS,
    check_rule=check_elements,
    scenario="static friction instead of GMS",
    experiments=(
        Experiment(
            group="prerolling",
            kind="prerolling",
            order=6,
            runs="feeddrive.experiments.prerolling_excitation:prerolling_runs",
            campaign="feeddrive.experiments.campaign:prerolling_jobs",
            plan="feeddrive.experiments.plan:PlanBuilder.prerolling",
            identifies="the Maxwell-slip elements (weights W_i, pre-rolling distances Delta_i): "
            "friction.N, nu, k (Eqs. 15-18)",
            short="pre-rolling",
            stem="prerolling",
            shape="reversing",
            file_pattern=r"prerolling",
            uses="pre-rolling W_i, Delta_i (Eqs. 15-18)",
        ),
    ),
    figures=(
        ReportFigure(
            "feeddrive.report.identification_figures:fig11_elements",
            "id_fig11_elements",
            "GMS elements identified (model of Fig. 11)",
            8,
        ),
        ReportFigure(
            "feeddrive.report.identification_figures:fig13_prerolling",
            "id_fig13_prerolling",
            "Analogue of Fig. 13: pre-rolling, measured and model",
            11,
        ),
    ),
)
