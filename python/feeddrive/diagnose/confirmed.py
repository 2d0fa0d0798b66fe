"""Which named effects the diagnosis confirmed, and the model that holds only those.

A step is **confirmed** when the verdict is ``explained`` (the final model leaves no more
than the noise floor allows, so every step is part of a model the data confirm), or when
the final residual where the step acted is close to the noise floor there: over the
samples of the step's ``where`` regimes (the regimes where its fit removed the most
residual per sample, :func:`localise.where`), the excess of the final residual over the
per-sample noise floor, ``sqrt(max(rms^2 - floor^2, 0))``, is below the gate a named
effect must explain (:mod:`significance`: ``max(3 x floor, 0.5 % of F_c)``).  The same
number decides the verdict over all samples; here it is applied where the effect acted.

A step that is not confirmed fitted something, but something else, no catalogue effect,
is still large where it acted: its parameters may have absorbed part of that (a sensor
latency fitted as viscous friction, a drifting force constant as a ripple).  Its fit is
kept in ``model_all_fits.json`` and left out of ``model.json``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ..data import Run
from ..model_file import ModelFile
from ..residual import RunResidual, gap, residuals
from .localise import regime_masks
from .significance import Gate

#: The rule, as diagnosis.json states it.
RULE = (
    "a step is confirmed when the verdict is explained, or when the final residual where it "
    "acted exceeds the noise floor there by less than the threshold a named effect must "
    "explain"
)


def confirm_steps(
    steps: Sequence[Any],
    res: Sequence[RunResidual],
    sigma: Sequence[np.ndarray],
    gate: Gate,
    explained: bool,
) -> list[dict]:
    """One record per step (``effect``, ``evidence['where']`` regimes): the final residual
    ``res`` and the noise floor ``sigma`` (per run, per sample [N]) over the regimes where it
    acted, the excess, the threshold and ``confirmed`` with the reason."""
    masks = [regime_masks(q) for q in res]
    out = []
    for s in steps:
        regimes = [w["regime"] for w in s.evidence.get("where", [])]
        sel = [np.zeros(len(q.r), bool) for q in res]
        for j, q in enumerate(res):
            for name in regimes:
                sel[j] |= masks[j].get(name, np.zeros(len(q.r), bool))
            sel[j] &= q.valid
        r = np.concatenate([q.r[m] for q, m in zip(res, sel, strict=True)])
        s2 = np.concatenate([sg[m] for sg, m in zip(sigma, sel, strict=True)])
        rec: dict = {"effect": s.effect, "regimes": regimes, "threshold_N": gate.threshold_N}
        if r.size:
            rms = float(np.sqrt(np.mean(r**2)))
            fl = float(np.sqrt(np.mean(s2**2)))
            rec.update(
                {
                    "rms_final_N": rms,
                    "floor_N": fl,
                    "excess_N": float(np.sqrt(max(rms**2 - fl**2, 0.0))),
                }
            )
        local = r.size > 0 and rec["excess_N"] < gate.threshold_N
        rec["confirmed"] = bool(explained or local)
        if explained:
            rec["why"] = "the verdict is explained: the final model leaves only the noise floor"
        elif local:
            rec["why"] = (
                f"where it acted ({', '.join(regimes)}) the final residual exceeds the "
                f"floor by {rec['excess_N']:.3g} N, below the {gate.threshold_N:.3g} N "
                "a named effect must explain"
            )
        else:
            ex = rec.get("excess_N")
            rec["why"] = (
                "where it acted ("
                + ", ".join(regimes)
                + ") the final residual still "
                + (f"exceeds the floor by {ex:.3g} N" if ex is not None else "is unknown")
                + f", above the {gate.threshold_N:.3g} N gate: something no catalogue "
                "effect models is there, and the fit may have absorbed part of it"
            )
        out.append(rec)
    return out


def confirmed_model(
    start: ModelFile, steps: Sequence[Any], records: Sequence[dict], final: ModelFile
) -> ModelFile:
    """The start model with only the confirmed steps applied (their effect switched on and
    the parameters they changed), ``final`` itself when every step is confirmed."""
    ok = [s for s, rec in zip(steps, records, strict=True) if rec["confirmed"]]
    if len(ok) == len(steps):
        return final
    effects = dict(start.effects)
    params = dict(start.parameters)
    for s in ok:
        if s.model_after is not None:
            effects[s.effect] = bool(s.model_after.effects[s.effect])
        params.update({k: p["value"] for k, p in s.parameters.items()})
    name = "+".join([start.name, *(s.effect for s in ok)])
    left = [s.effect for s, rec in zip(steps, records, strict=True) if not rec["confirmed"]]
    desc = (
        f"{start.name} with the effects the diagnosis confirmed ({', '.join(s.effect for s in ok) or 'none'}); "
        f"fitted but not confirmed (in model_all_fits.json): {', '.join(left)}"
    )
    return ModelFile(name=name, effects=effects, parameters=params, description=desc)


def confirmation_of(
    runs: Sequence[Run],
    steps: Sequence[Any],
    start: ModelFile,
    final: ModelFile,
    res_start: Sequence[RunResidual],
    res_final: Sequence[RunResidual],
    sigma: Sequence[np.ndarray],
    gate: Gate,
    explained: bool,
    kw: dict,
) -> tuple[ModelFile, dict]:
    """The confirmed model (model.json) and diagnosis.json ``confirmation``: the rule, the
    record of every step (:func:`confirm_steps`) and, for model.json and
    model_all_fits.json, the name, the force gap over all runs [N] and the effects added
    (``kw``: the residual's keywords, to compute the confirmed model's gap)."""
    records = confirm_steps(steps, res_final, sigma, gate, explained)
    kept = confirmed_model(start, steps, records, final)
    if kept is final:
        kept_gap = gap(list(res_final))
    elif not any(r["confirmed"] for r in records):
        kept_gap = gap(list(res_start))
    else:
        kept_gap = gap(residuals(list(runs), kept, **kw))
    return kept, {
        "rule": RULE,
        "steps": records,
        "model_json": {
            "file": "model.json",
            "name": kept.name,
            "gap_N": kept_gap,
            "effects_added": [r["effect"] for r in records if r["confirmed"]],
        },
        "model_all_fits_json": {
            "file": "model_all_fits.json",
            "name": final.name,
            "gap_N": gap(list(res_final)),
            "effects_added": [s.effect for s in steps],
        },
    }
