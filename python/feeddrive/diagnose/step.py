"""One step of the diagnosis: its record, the identification of the added effect with
polishing, and its confirmation on the re-computed residual (also for the compliance step
the wide band (:mod:`band`) found)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..data import Run
from ..model_file import ModelFile
from ..residual import RunResidual, gap, residuals
from .band import WideBand
from .candidates import CANDIDATES
from .changes import changed_parameters, force_change, parameter_changes
from .closed_loop import closed_loop_gap
from .context import Context
from .localise import localise, where
from .ranking import summary
from .scoring import Score, score
from .significance import Gate, explained_force

#: Polishing: at most this many re-identifications of the added effect, each only when the
#: refit removes at least POLISH_MIN of the re-computed residual's energy in sample.
POLISH_ITER = 2
POLISH_MIN = 0.05
#: A re-computed residual must shrink by at least this share of the gap to confirm a step.
CONFIRM = 0.02


@dataclass
class Step:
    """One named effect: evidence, identified parameters, gap before and after."""

    effect: str
    decision: str  #: "missing_effect", "refinement" or "ambiguous"
    ambiguous_with: list[str]
    evidence: dict
    parameters: dict
    gap_before: dict
    gap_after: dict
    model_after: ModelFile
    effect_was_on: bool = False  #: the step corrected values of an effect already on
    residual_before: list[RunResidual] = field(default_factory=list, repr=False)
    residual_after: list[RunResidual] = field(default_factory=list, repr=False)

    def to_json(self) -> dict:
        out = {
            "effect": self.effect,
            "decision": self.decision,
            "ambiguous_with": self.ambiguous_with,
            "effect_was_on": self.effect_was_on,
            "evidence": self.evidence,
            "parameters": self.parameters,
            "gap_before": self.gap_before,
            "gap_after": self.gap_after,
        }
        if self.effect_was_on:
            fc = force_change(self.residual_before, self.residual_after)
            out["refinement"] = {
                "force_change_rms_N": fc,
                "force_change_percent_of_gap": 100.0
                * fc
                / max(self.gap_before["force_rms_N"], 1e-300),
            }
        return out


def _gap_record(res: list[RunResidual], regimes: list[str], cl: dict | None) -> dict:
    loc = localise(res)
    out = {
        "force_rms_N": gap(res),
        "where": {k: loc["regimes"][k]["rms"] for k in regimes if k in loc["regimes"]},
    }
    if cl is not None:
        out.update(cl)
    return out


def polish(
    runs: list[Run],
    effect: str,
    model: ModelFile,
    res: list[RunResidual],
    n_blocks: int,
    kw: dict,
    max_iter: int = POLISH_ITER,
) -> tuple[ModelFile, list[RunResidual], int]:
    """Re-identify ``effect`` on the residual re-computed with it (the candidates are
    linearised around the previous model: the GMS element limits, the sliding fraction and
    the stuck samples move when the effect changes).  An iteration is kept when the
    re-computed gap shrinks by at least ``CONFIRM``."""
    n = 0
    for _ in range(max_iter):
        ctx = Context(res, model, n_blocks=n_blocks)
        variants = CANDIDATES[effect](ctx)
        if not variants:
            break
        best = max((score(ctx, v) for v in variants), key=lambda s: s.improvement_in_sample)
        if best.improvement_in_sample < POLISH_MIN:
            break
        trial = best.variant.to_model(best.theta)
        trial.name = model.name
        trial_res = residuals(runs, trial, **kw)
        if gap(trial_res) > (1.0 - CONFIRM) * gap(res):
            break
        model, res, n = trial, trial_res, n + 1
    return model, res, n


def _evidence(
    cand: Score, ctx: Context, ranking: list[Score], n_polish: int, wh: list[dict], gate: Gate
) -> dict:
    """What a step's decision rests on (diagnosis.json ``evidence``)."""
    return {
        "statistic": "held-out share of force-residual energy removed (blocks)",
        "heldout_improvement": cand.improvement,
        "t_blocks": cand.t,
        "explained_force_N": explained_force(cand),
        "threshold_N": gate.threshold_N,
        "x_noise_floor": explained_force(cand) / max(gate.floor_N, 1e-300),
        "blocks_improved": f"{cand.blocks_improved}/{ctx.blocks}",
        "in_sample_improvement": cand.improvement_in_sample,
        "variant": cand.variant.label,
        "refinement": cand.variant.refine,
        "polish_iterations": n_polish,
        "where": wh,
        "ranking": [summary(s, gate) for s in ranking[:6]],
    }


def confirm_step(
    runs: list[Run],
    ctx: Context,
    cand: Score,
    group: list[Score],
    ranking: list[Score],
    cl: dict | None,
    name: str,
    n_blocks: int,
    kw: dict,
    gate: Gate,
) -> tuple[Step, dict | None] | None:
    """Add ``cand`` to the context's model, identify it on all data (with polishing) and
    re-compute the residual; the step and the new closed-loop gap when the gap shrinks by
    at least ``CONFIRM``, else None.  ``group``: ``cand`` and the candidates it cannot be
    told from."""
    current, res = ctx.model, ctx.res
    new_model = cand.variant.to_model(cand.theta)
    new_model.name = name
    new_res = residuals(runs, new_model, **kw)
    new_model, new_res, n_polish = polish(
        runs, cand.variant.effect, new_model, new_res, n_blocks, kw
    )
    if gap(new_res) > (1.0 - CONFIRM) * gap(res):
        return None
    wh = where(localise(res), localise(res, ctx.unstack(cand.r_fit)))
    regimes = [w["regime"] for w in wh]
    cl_after = closed_loop_gap(runs, new_model) if cl is not None else None
    ga = _gap_record(new_res, regimes, cl_after)
    ga["force_rms_heldout_N"] = float(np.sqrt(np.mean(cand.r_heldout**2)))
    was_on = bool(current.effects[cand.variant.effect])
    decision = "ambiguous" if len(group) > 1 else "refinement" if was_on else "missing_effect"
    step = Step(
        effect=cand.variant.effect,
        decision=decision,
        ambiguous_with=[s.variant.effect for s in group[1:]],
        evidence=_evidence(cand, ctx, ranking, n_polish, wh, gate),
        parameters=parameter_changes(changed_parameters(current, new_model)),
        gap_before=_gap_record(res, regimes, cl),
        gap_after=ga,
        model_after=new_model,
        effect_was_on=was_on,
        residual_before=res,
        residual_after=new_res,
    )
    return step, cl_after


def wide_band_step(
    runs: list[Run],
    res: list[RunResidual],
    wb: WideBand,
    cl: dict | None,
    name: str,
    n_blocks: int,
    kw: dict,
) -> tuple[Step, dict | None] | None:
    """The compliance step the wide-band look (:mod:`band`) confirmed, identified there and
    confirmed on the diagnosis's own residual: its gap must shrink by ``CONFIRM``."""
    c = wb.compliance
    if c is None:
        return None
    found = confirm_step(runs, wb.context, c, [c], [c, wb.mass], cl, name, n_blocks, kw, wb.gate)
    if found is None or found[0].gap_after["force_rms_N"] > (1.0 - CONFIRM) * gap(res):
        return None
    step, cl_after = found
    step.gap_before = _gap_record(res, list(step.gap_after["where"]), cl)
    step.residual_before = res
    step.evidence["band"] = wb.to_json()
    return step, cl_after


def band_record(wb: WideBand, lead: Score) -> dict:
    """What the verdict says when a resonance shows through the wide band but is not
    confirmed: the band of the data, the resonance glimpsed and the mass it would be taken
    for (not named)."""
    c = wb.compliance
    if c is None:  # a trace or a confirmation has its compliance variant
        raise ValueError("diagnose: a band record needs the wide band's compliance variant")
    dm = float(lead.theta[0])
    out: dict[str, Any] = {**wb.to_json(), "mass_change_kg": dm}
    out["sentence"] = (
        f"The mass-like part of the residual (a mass change of {dm:+.3g} kg) rings: through a "
        f"{wb.window}-sample acceleration window (band {wb.wide_band_Hz:.0f} Hz; the diagnosis's "
        f"window resolves {wb.band_Hz:.0f} Hz) a load on a spring ({c.variant.label}) removes "
        f"{wb.share_beyond:.0%} of what the mass leaves on held-out blocks (t = "
        f"{wb.t_beyond:.2g}, {wb.force_beyond_N:.3g} N against a floor of {wb.gate.floor_N:.3g} N "
        "there), too little to confirm it: the data cannot tell a load resonating at or above "
        f"{wb.band_Hz:.0f} Hz from a mass change, so neither is named; excite the band (moves "
        "with sharp acceleration steps, a PRBS) or record a faster, finer position."
    )
    return out
