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

The stages, in the order of the loop: :mod:`ranking` (the best variant of every family,
the effect to add), :mod:`step` (its identification, polishing and confirmation, with
:mod:`changes` and :mod:`closed_loop` recording what it changes), :mod:`verdict`; the
record they fill is :mod:`diagnosis`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..data import Run
from ..harness.controllers import CONTROLLERS
from ..model_file import ModelFile
from ..physics import compile
from ..residual import gap, residuals
from .band import wide_band
from .closed_loop import closed_loop_gap
from .confirmed import confirmation_of
from .context import DEFAULT_BLOCKS, Context
from .diagnosis import Diagnosis
from .hints import add_hint
from .hints import hints as fit_hints
from .noise_floor import noise_floor
from .ranking import NESTED, NESTS_IN, choose, rank, stop_record
from .scoring import I_MIN, T_MIN
from .significance import NOISE_FACTOR, PRACTICAL_SHARE, make_gate, passes
from .step import CONFIRM, Step, band_record, confirm_step, wide_band_step
from .verdict import verdict

__all__ = ["NESTED", "Diagnosis", "Step", "closed_loop_gap", "diagnose"]


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
            found = wide_band_step(runs, res, wb, cl, name, n_blocks, kw)
            if found is not None:
                step, cl = found
                steps.append(step)
                current, res = step.model_after, step.residual_after
                continue
        if wb is not None and lead is not None and (wb.trace or wb.confirmed):
            band = band_record(wb, lead)
            stop = {**stop_record(band["sentence"], ranking, res, gate), "band": band}
            break
        if lead is None:
            stop = stop_record(
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
            stop = stop_record(
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
