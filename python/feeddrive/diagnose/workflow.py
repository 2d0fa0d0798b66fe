"""The discrepancy loop: residual -> localise -> score candidates -> add the best -> repeat.

Each step computes the force residual of the current model along every run, scores every
candidate of the effect catalogue on held-out blocks (:mod:`scoring`), names the best significant one
(or an ambiguous group, of which the most parsimonious is added), identifies its parameters
on all data, re-computes the residual with the new model (the full model, not the linear
prediction) and records the gap before and after, overall and where the candidate acted.
The loop stops when nothing is significant, when the re-computed residual does not confirm
the improvement, or after ``max_steps``.

Significant means held-out significant (:mod:`scoring`) *and* above the absolute gates of
:mod:`significance`: the force the candidate explains on held-out blocks must exceed 3 x
the run's noise floor (:mod:`noise_floor`) and 0.5 % of the Coulomb level.  A step's
``decision`` is ``missing_effect`` (the effect was off and is switched on), ``refinement``
(the values of an effect already on, with the old and new values and the force the change
makes) or ``ambiguous`` (the group the data cannot separate).  The final ``verdict`` is
``explained`` when the residual's excess over the floor is below the same gates, else
``unexplained_residual`` with its size, where it sits (:func:`localise.excess_location`,
and in time: :mod:`timeaxis`) and the best signature outside the catalogue as a hint
(:mod:`hints`; never a model change).  ``model`` holds every fit; ``model_confirmed`` only
the steps :mod:`confirmed` confirms (the two model files of the diagnosis).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from collections.abc import Set as AbstractSet
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..data import Run
from ..effects import nesting
from ..harness.controllers import CONTROLLERS
from ..harness.runs import replay
from ..harness.sidecar import read_sidecar
from ..model_file import ModelFile
from ..physics import compile
from ..residual import RunResidual, gap, residuals
from .band import WideBand, wide_band
from .candidates import CANDIDATES
from .confirmed import confirmation_of
from .context import DEFAULT_BLOCKS, Context
from .hints import add_hint
from .hints import hints as fit_hints
from .localise import (
    displacement_since_reversal,
    excess_location,
    localise,
    spatial_spectrum,
    spectral_peaks,
    where,
)
from .noise_floor import NoiseFloor, floor_table, noise_floor
from .scoring import AMBIGUITY, I_MIN, T_MIN, Score, score, separable
from .significance import (
    NOISE_FACTOR,
    PRACTICAL_SHARE,
    Gate,
    excess,
    explained_force,
    make_gate,
    nested_separable,
    passes,
)
from .timeaxis import time_axis, trend_text

#: Travel after a reversal [m] within which the closed-loop error counts as reversal error.
REVERSAL_ZONE = 1e-3
#: Polishing: at most this many re-identifications of the added effect, each only when the
#: refit removes at least POLISH_MIN of the re-computed residual's energy in sample.
POLISH_ITER = 2
POLISH_MIN = 0.05
#: A richer variant of the same effect must remove this much more held-out energy.
PARSIMONY = 0.01
#: A re-computed residual must shrink by at least this share of the gap to confirm a step.
CONFIRM = 0.02
#: A family that reduces to another in a limit (a load on a spring is a mass for
#: frequencies far below its resonance) is ranked only when held-out data show it beyond
#: that family's best (:func:`significance.nested_separable`): else the simpler one
#: explains as much.  By id, the limit family's id (the registry's ``Candidate.limit``).
NESTED = nesting()
#: The family that nests in each limit family: a lead of the limit family is looked at
#: again through a wider band for it (:mod:`band`).
NESTS_IN = {limit: eid for eid, limit in NESTED.items()}

_UNITS = {
    "compliance.m2": "kg",
    "compliance.f": "Hz",
    "compliance.zeta": "1",
    "compliance.sensor_side": "1",
    "m": "kg",
    "offset.F": "N",
    "friction.F_s": "N",
    "friction.F_c": "N",
    "friction.V_s": "m/s",
    "friction.delta": "1",
    "friction.sigma2": "N s/m",
    "friction.C": "N/s",
    "friction.N": "1",
    "asymmetry.dF": "N",
    "asymmetry.dsigma2": "N s/m",
}


def unit(name: str) -> str:
    """SI unit of an FMU parameter."""
    if name in _UNITS:
        return _UNITS[name]
    if name.startswith(("friction.nu", "friction_profile.c[")) or name == "friction_profile.n":
        return "1"
    if name in ("friction_profile.x_start", "friction_profile.x_end"):
        return "m"
    if name.startswith("friction.k"):
        return "N/m"
    if name.endswith("]") and ".lambda[" in name:
        return "m"
    for mp, u in (("cogging", "N"), ("ripple", "N/A")):
        if name.startswith(f"{mp}.c["):
            k = int(name[len(mp) + 3 : -1])
            return u if k == 0 else f"{u}/m^{k}" if k > 1 else f"{u}/m"
        if name.startswith((f"{mp}.a[", f"{mp}.b[")):
            return u
    return "?"


def changed_parameters(before: ModelFile, after: ModelFile) -> dict:
    """Parameters whose value changed (and effect switches), with units and old values."""
    out: dict = {}
    for k, v in after.parameters.items():
        old = before.parameters[k]
        if v != old:
            out[k] = {"value": v, "unit": unit(k), "before": old}
    return out


def parameter_changes(params: dict) -> dict:
    """``changed_parameters`` with the relative change of each value [%] (None from 0)."""
    out = {}
    for k, p in params.items():
        v, b = p["value"], p["before"]
        pct = None
        if (
            isinstance(v, (int, float))
            and isinstance(b, (int, float))
            and b != 0
            and not isinstance(v, bool)
        ):
            pct = 100.0 * (float(v) - float(b)) / abs(float(b))
        out[k] = {**p, "change_percent": pct}
    return out


def force_change(before: list[RunResidual], after: list[RunResidual]) -> float:
    """rms over all runs of the change of the model force between two models [N]."""
    d = np.concatenate(
        [(qb.r - qa.r)[qb.valid & qa.valid] for qb, qa in zip(before, after, strict=True)]
    )
    return float(np.sqrt(np.mean(d**2))) if d.size else 0.0


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


@dataclass
class Diagnosis:
    """The ordered steps, the stop record, the start and final models."""

    steps: list[Step]
    stop: dict
    model_start: ModelFile
    model: ModelFile
    runs: list[str]
    notes: list[str]
    residual_start: list[RunResidual] = field(default_factory=list, repr=False)
    residual_final: list[RunResidual] = field(default_factory=list, repr=False)
    floors: list[NoiseFloor] = field(default_factory=list, repr=False)
    gate: Gate | None = None
    verdict: dict = field(default_factory=dict)
    #: the start model with only the confirmed steps (model.json); ``model`` has every fit
    model_confirmed: ModelFile | None = None
    #: per step: confirmed or not and why (:mod:`confirmed`), and the confirmed model's gap
    confirmation: dict = field(default_factory=dict)

    @property
    def named(self) -> list[str]:
        """Effects added, in order."""
        return [s.effect for s in self.steps if s.effect is not None]

    def to_json(self) -> dict:
        return {
            "schema": "feeddrive.diagnosis/2",
            "runs": self.runs,
            "model_start": self.model_start.name,
            "notes": self.notes,
            "verdict": self.verdict,
            "noise_floor": floor_table(self.residual_start, self.floors) if self.floors else {},
            "initial_friction": {
                q.name: q.start.to_json(q.Ts) for q in self.residual_start if q.start is not None
            },
            "significance": self.gate.to_json() if self.gate else {},
            "localisation_start": localisation_summary(self.residual_start, self.floors),
            "steps": [s.to_json() for s in self.steps],
            "stop": self.stop,
            "final_model": self.model.name,
            "confirmation": self.confirmation,
            "localisation_final": localisation_summary(self.residual_final, self.floors),
        }


def localisation_summary(res: list[RunResidual], floors: list[NoiseFloor] | None = None) -> dict:
    """Regime and position table of a residual, the peaks of its spatial spectra and its
    time axis (per time block of each run, with the noise floor when ``floors`` are given)."""
    if not res:
        return {}
    loc = localise(res)
    loc["time"] = time_axis(res, [f.sigma for f in floors] if floors else None)
    peaks = {}
    for weight, key in ((None, "cogging_like_N"), ("i", "ripple_like_N_per_A")):
        if weight == "i" and any(q.i is None for q in res):
            continue
        lams, amps = spatial_spectrum(res, weight=weight)
        peaks[key] = [
            {"wavelength_m": lam, "amplitude": a}
            for lam, a in spectral_peaks(lams, amps, n_peaks=3)
        ]
    loc["spectrum_peaks"] = peaks
    return loc


def closed_loop_gap(runs: list[Run], model: ModelFile) -> dict | None:
    """Closed-loop position error of ``model`` re-simulated with each run's controller.

    Only runs that have ``x_ref`` and whose sidecar (:mod:`feeddrive.harness.sidecar`)
    names a controller the registry builds (:data:`~feeddrive.harness.controllers.
    CONTROLLERS`) count; None when there is none.  The replay
    (:func:`feeddrive.harness.runs.replay`) reads the position at the run's
    ``sensors.quantum``, without noise, under the run's load.  Returns rms and max
    |x_sim - x_meas| [m], and the max within ``REVERSAL_ZONE`` of travel after a reversal
    (the reversal error).
    """
    errs, near = [], []
    for run in runs:
        side = read_sidecar(run.meta, where=f"{run.path or run.name}: sidecar", run=run)
        if side.controller is None or run.x_ref is None:
            continue
        x_sim = replay(model.fmu_parameters(), run, side)
        errs.append(side.sensors.quantise(x_sim) - np.asarray(run.x))
        near.append(displacement_since_reversal(np.asarray(run.x)) < REVERSAL_ZONE)
    if not errs:
        return None
    e = np.concatenate(errs)
    nz = np.concatenate(near)
    return {
        "position_error_rms_m": float(np.sqrt(np.mean(e**2))),
        "position_error_max_m": float(np.max(np.abs(e))),
        "reversal_error_max_m": float(np.max(np.abs(e[nz]))) if nz.any() else None,
    }


def _gap_record(res: list[RunResidual], regimes: list[str], cl: dict | None) -> dict:
    loc = localise(res)
    out = {
        "force_rms_N": gap(res),
        "where": {k: loc["regimes"][k]["rms"] for k in regimes if k in loc["regimes"]},
    }
    if cl is not None:
        out.update(cl)
    return out


def rank(ctx: Context, gate: Gate, skip: AbstractSet[str] = frozenset()) -> list[Score]:
    """The best variant of every candidate family, best held-out improvement first; a
    ``NESTED`` family only when it shows beyond its limit family
    (:func:`significance.nested_separable`)."""
    best: list[Score] = []
    for eid, make in CANDIDATES.items():
        if eid in skip:
            continue
        scores = [score(ctx, v) for v in make(ctx)]
        if scores:
            top = max(scores, key=lambda s: s.improvement)
            # parsimony within a family: fewer parameters unless they cost > PARSIMONY
            lean = [
                s
                for s in scores
                if s.variant.n_params < top.variant.n_params
                and s.improvement >= top.improvement - PARSIMONY
            ]
            if lean:
                top = max(lean, key=lambda s: (-s.variant.n_params, s.improvement))
            if not top.significant:
                # variants held-out data cannot tell from the best (within AMBIGUITY of its
                # improvement, no more parameters): one whose gain is consistent over the
                # blocks shows the effect where the best's gain rests on a few blocks
                near = [
                    s
                    for s in scores
                    if s.significant
                    and s.variant.n_params <= top.variant.n_params
                    and s.improvement >= (1.0 - AMBIGUITY) * top.improvement
                ]
                if near:
                    top = max(near, key=lambda s: s.improvement)
            best.append(top)
    by_id = {s.variant.effect: s for s in best}
    for eid, limit in NESTED.items():
        if eid in by_id and limit in by_id and not nested_separable(by_id[eid], by_id[limit], gate):
            best.remove(by_id[eid])
    best.sort(key=lambda s: -s.improvement)
    return best


def _told_apart(lead: Score, other: Score, gate: Gate) -> bool:
    """Held-out data separate ``lead`` from ``other``: :func:`scoring.separable`, or, for a
    ``NESTED`` family leading its limit family, :func:`significance.nested_separable`."""
    a, b = lead.variant.effect, other.variant.effect
    if NESTED.get(a) == b and nested_separable(lead, other, gate):
        return True
    return separable(lead, other)


def choose(ranking: list[Score], gate: Gate) -> tuple[Score | None, list[Score]]:
    """The effect to add and the candidates the data cannot separate from it.

    Among candidates that pass (held-out significant and above the ``gate``,
    :func:`significance.passes`) the best held-out improvement leads; every passing
    candidate not :func:`separable` from it joins its group; the group member with the
    fewest parameters (then the best improvement) is added, the others are reported.
    """
    sig = [s for s in ranking if passes(s, gate)]
    if not sig:
        return None, []
    lead = sig[0]
    group = [lead] + [s for s in sig[1:] if not _told_apart(lead, s, gate)]
    group.sort(key=lambda s: (s.variant.n_params, -s.improvement))
    return group[0], group[1:]


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


def _summary(s: Score, gate: Gate | None = None) -> dict:
    out = {
        "effect": s.variant.effect,
        "variant": s.variant.label,
        "heldout_improvement": s.improvement,
        "t_blocks": s.t,
        "blocks_improved": s.blocks_improved,
        "significant": s.significant,
        "refinement": s.variant.refine,
        "explained_force_N": explained_force(s),
    }
    if gate is not None:
        out["above_threshold"] = explained_force(s) >= gate.threshold_N
    return out


def _stop(reason: str, ranking: list[Score], res: list[RunResidual], gate: Gate) -> dict:
    return {"reason": reason, "ranking": [_summary(s, gate) for s in ranking[:6]], "gap": gap(res)}


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
        "ranking": [_summary(s, gate) for s in ranking[:6]],
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


def _wide_band_step(
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


def _band_record(wb: WideBand, lead: Score) -> dict:
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


def _where_text(loc: dict) -> str:
    """One phrase of where an excess sits (verdict sentence)."""
    sb = loc["stroke_band"]
    parts = [f"x {sb['x_lo_m'] * 1e3:.1f}-{sb['x_hi_m'] * 1e3:.1f} mm"]
    for key in ("speed", "direction", "since_reversal"):
        if loc[key]["regime"]:
            parts.append(loc[key]["regime"])
    fb = loc["frequency_band"]
    if fb:
        parts.append(f"{fb['f_lo_Hz']:g}-{fb['f_hi_Hz']:g} Hz")
    wl = loc["wavelength"]
    if wl:
        parts.append(f"wavelength {wl['wavelength_m'] * 1e3:.3g} mm")
    return ", ".join(parts)


def verdict(
    res: list[RunResidual], floors: list[NoiseFloor], gate: Gate, band: dict | None = None
) -> dict:
    """``explained`` when the final residual's excess over the noise floor is below the gate
    (:mod:`significance`), else ``unexplained_residual`` with its size and location; a
    ``band`` record (a resonance the data's band cannot confirm, :mod:`band`) is added with
    its sentence."""
    g = gap(res)
    e = excess(g, gate.floor_N)
    out: dict[str, Any] = {
        "gap_N": g,
        "noise_floor_N": gate.floor_N,
        "excess_N": e,
        "x_noise_floor": g / max(gate.floor_N, 1e-300),
        "threshold_N": gate.threshold_N,
    }
    if e < gate.threshold_N:
        out["verdict"] = "explained"
        out["sentence"] = (
            f"Explained: the residual left ({g:.3g} N rms, "
            f"{out['x_noise_floor']:.1f} x the noise floor {gate.floor_N:.3g} N) "
            f"exceeds the floor by {e:.3g} N, less than the {gate.threshold_N:.3g} N "
            "a named effect must explain."
        )
        return out
    loc = excess_location(res, [f.sigma for f in floors])
    loc["time"] = time_axis(res, [f.sigma for f in floors])
    trend = trend_text(loc["time"])
    out["verdict"] = "unexplained_residual"
    out["where"] = loc
    out["sentence"] = (
        f"Unexplained residual: {g:.3g} N rms ({out['x_noise_floor']:.1f} x the "
        f"noise floor {gate.floor_N:.3g} N) that no catalogue effect explains, "
        f"mostly at {_where_text(loc)}" + (f"; {trend}" if trend else "") + "."
    )
    if band is not None:
        out["band"] = band
        out["sentence"] += " " + band["sentence"]
    return out


def diagnose(
    runs: list[Run],
    model: ModelFile,
    max_steps: int = 4,
    force_gain: float | None = None,
    window: int | None = None,
    n_blocks: int = DEFAULT_BLOCKS,
    closed_loop: bool = True,
    notes: Sequence[str] = (),
    progress: Callable[[str], None] | None = None,
) -> Diagnosis:
    """Diagnose what ``model`` lacks against measured ``runs`` (see module docstring).

    Parameters
    ----------
    runs : measured runs (recordings); several runs are pooled, blocks are cut per run.
    model : the starting model file.
    max_steps : at most this many effects are added.
    force_gain : N/V for runs without current (else the sidecar's, else the model's loop).
    window : Savitzky-Golay window of the acceleration estimate [samples] (None: 20 ms).
    n_blocks : held-out blocks over all runs.
    closed_loop : also re-simulate runs whose sidecar describes their controller.
    notes : lines said about the inputs (what a sidecar said that was not used), kept first
        in the diagnosis's notes.
    progress : called with each stage's name as it starts (a progress bar).
    """
    if not runs:
        raise ValueError("diagnose: no runs given")
    stage = progress or (lambda name: None)
    stage("force residual, noise floor")
    kw = {"force_gain": force_gain, "window": window}
    current = model
    res = start_res = residuals(runs, current, **kw)
    plant = compile(model)
    floors = [noise_floor(run, q, plant, force_gain) for run, q in zip(runs, res, strict=True)]
    floor_N = float(
        np.sqrt(
            np.mean(
                np.concatenate([f.sigma[q.valid] ** 2 for f, q in zip(floors, res, strict=True)])
            )
        )
    )
    gate = make_gate(model, res, floor_N)
    notes = list(notes) + sorted({q.force_source for q in res})
    steps: list[Step] = []
    if closed_loop:
        stage("closed-loop gap")
    cl = closed_loop_gap(runs, current) if closed_loop else None
    if closed_loop and cl is None:
        notes.append(
            "closed-loop gap not computed: no run has x_ref and a sidecar 'controller' "
            f"the registry builds (types {', '.join(map(repr, CONTROLLERS))}; the "
            "sidecar lines above say what was not understood)"
        )
    stop: dict[str, Any] = {"reason": f"max_steps = {max_steps} reached"}
    for k in range(max_steps):
        stage(f"step {k + 1}: candidates")
        ctx = Context(res, current, n_blocks=n_blocks)
        ranking = rank(ctx, gate)
        lead, others = choose(ranking, gate)
        load = NESTS_IN.get(lead.variant.effect) if lead is not None else None
        wb = (
            wide_band(
                runs,
                current,
                res,
                n_blocks,
                force_gain,
                load=load,
                limit=lead.variant.effect,
            )
            if lead is not None and load is not None
            else None
        )
        if wb is not None and wb.confirmed and load is not None:
            name = f"{model.name}+{'+'.join([*(s.effect for s in steps), load])}"
            found = _wide_band_step(runs, res, wb, cl, name, n_blocks, kw)
            if found is not None:
                step, cl = found
                steps.append(step)
                current, res = step.model_after, step.residual_after
                continue
        if wb is not None and lead is not None and (wb.trace or wb.confirmed):
            band = _band_record(wb, lead)
            stop = {**_stop(band["sentence"], ranking, res, gate), "band": band}
            break
        if lead is None:
            stop = _stop(
                f"no candidate removes >= {I_MIN:.0%} of the residual energy on "
                f"held-out blocks with t >= {T_MIN:g} and explains at least "
                f"{gate.threshold_N:.3g} N (the larger of {NOISE_FACTOR:g} x the noise "
                f"floor {gate.floor_N:.3g} N and {PRACTICAL_SHARE:.1%} of the friction "
                f"level {gate.level_N:.3g} N)",
                ranking,
                res,
                gate,
            )
            break
        tried = [lead] + [s for s in ranking if passes(s, gate) and s is not lead]
        found = None
        for cand in tried[:3]:
            name = f"{model.name}+{'+'.join([*(s.effect for s in steps), cand.variant.effect])}"
            group = [cand] + (list(others) if cand is lead else [])
            found = confirm_step(runs, ctx, cand, group, ranking, cl, name, n_blocks, kw, gate)
            if found is not None:
                break
        if found is None:
            stop = _stop(
                "the significant candidates did not shrink the re-computed residual "
                f"by {CONFIRM:.0%}",
                ranking,
                res,
                gate,
            )
            break
        step, cl = found
        steps.append(step)
        current, res = step.model_after, step.residual_after
    else:
        stop["gap"] = gap(res)
    stage("verdict, confirmation")
    v = verdict(res, floors, gate, stop.get("band"))
    if v["verdict"] == "unexplained_residual":
        v = add_hint(v, fit_hints(runs, current, res, kw), gate)
    kept, confirmation = confirmation_of(
        runs,
        steps,
        model,
        current,
        start_res,
        res,
        [f.sigma for f in floors],
        gate,
        v["verdict"] == "explained",
        kw,
    )
    return Diagnosis(
        steps=steps,
        stop=stop,
        model_start=model,
        model=current,
        runs=[r.name or f"run{j}" for j, r in enumerate(runs)],
        notes=notes,
        residual_start=start_res,
        residual_final=res,
        floors=floors,
        gate=gate,
        verdict=v,
        model_confirmed=kept,
        confirmation=confirmation,
    )
