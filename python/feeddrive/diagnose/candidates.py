"""The diagnosis's candidate families, one per effect of the catalogue (docs/effects.md).

Each effect module of :mod:`feeddrive.effects` builds its own variants
(``candidate(ctx) -> list[Variant]``, named by its ``Effect.candidate.builder``), from the
services of :class:`~feeddrive.diagnose.context.Context`
(:class:`feeddrive.effects.candidate.CandidateContext`); this module collects them in the
registry's order.
"""

from __future__ import annotations

from typing import cast

from ..effects import EFFECTS, Effect, resolve
from ..effects.candidate import Builder, Variant


def _builder(e: Effect) -> Builder:
    """The candidate family of effect ``e`` (the function its registry reference names)."""
    make = resolve(e.candidate.builder)
    if not callable(make):
        raise ImportError(f"effect {e.id}: candidate {e.candidate.builder!r} is not a function")
    return cast(Builder, make)


#: Every candidate family, by catalogue id (the registry's order: feeddrive.effects.EFFECTS).
CANDIDATES: dict[str, Builder] = {e.id: _builder(e) for e in EFFECTS}

__all__ = ["CANDIDATES", "Variant"]
