"""Ranking the candidates: the best variant of every family, the effect to add and the
candidates held-out data cannot tell from it, and the ranking's summary records."""

from __future__ import annotations

from collections.abc import Set as AbstractSet

from ..effects import nesting
from ..residual import RunResidual, gap
from .candidates import CANDIDATES
from .context import Context
from .scoring import AMBIGUITY, Score, score, separable
from .significance import Gate, explained_force, nested_separable, passes

#: A richer variant of the same effect must remove this much more held-out energy.
PARSIMONY = 0.01
#: A family that reduces to another in a limit (a load on a spring is a mass for
#: frequencies far below its resonance) is ranked only when held-out data show it beyond
#: that family's best (:func:`significance.nested_separable`): else the simpler one
#: explains as much.  By id, the limit family's id (the registry's ``Candidate.limit``).
NESTED = nesting()
#: The family that nests in each limit family: a lead of the limit family is looked at
#: again through a wider band for it (:mod:`band`).
NESTS_IN = {limit: eid for eid, limit in NESTED.items()}


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


def summary(s: Score, gate: Gate | None = None) -> dict:
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


def stop_record(reason: str, ranking: list[Score], res: list[RunResidual], gate: Gate) -> dict:
    return {"reason": reason, "ranking": [summary(s, gate) for s in ranking[:6]], "gap": gap(res)}
