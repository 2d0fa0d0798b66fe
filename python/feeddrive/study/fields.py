"""Reading a study file's fields: a number, an integer, an object with its allowed keys, an
object of a known ``type``; :class:`StudyError` names the file and the field of a problem."""

from __future__ import annotations

import math
from collections.abc import Collection, Iterable
from typing import Any


class StudyError(ValueError):
    """A study file that breaks the format: names the file and the field."""

    def __init__(self, source: str, fld: str, problem: str) -> None:
        self.source, self.field, self.problem = source, fld, problem
        super().__init__(f"{source}: field {fld}: {problem}")


def number_field(
    v: Any, src: str, fld: str, positive: bool = False, minimum: float | None = None
) -> float:
    """The finite number ``v`` of field ``fld`` (> 0 with ``positive``, >= ``minimum``)."""
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise StudyError(src, fld, f"must be a finite number, got {v!r}")
    if positive and not v > 0:
        raise StudyError(src, fld, f"must be > 0, got {v!r}")
    if minimum is not None and v < minimum:
        raise StudyError(src, fld, f"must be >= {minimum}, got {v!r}")
    return float(v)


def integer_field(v: Any, src: str, fld: str, minimum: int = 1) -> int:
    """The integer ``v`` of field ``fld``, >= ``minimum``."""
    if isinstance(v, bool) or not isinstance(v, int) or v < minimum:
        raise StudyError(src, fld, f"must be an integer >= {minimum}, got {v!r}")
    return v


def object_field(
    v: Any, src: str, fld: str, allowed: tuple[str, ...] | None = None
) -> dict[str, Any]:
    """The JSON object ``v`` of field ``fld``, its keys among ``allowed`` when given."""
    if not isinstance(v, dict):
        raise StudyError(src, fld, f"must be an object, got {type(v).__name__}")
    if allowed is not None:
        bad = sorted(set(v) - set(allowed))
        if bad:
            raise StudyError(src, f"{fld}.{bad[0]}", f"unknown key (allowed: {', '.join(allowed)})")
    return v


def typed_object_field(
    v: Any, src: str, fld: str, known: Collection[str], what: str, listed: Iterable[str] = ()
) -> tuple[dict[str, Any], str]:
    """The JSON object ``v`` of field ``fld`` and its ``type``, one of ``known`` (a ``what``;
    the message lists ``listed``, else ``known``)."""
    raw = object_field(v, src, fld)
    kind = raw.get("type")
    if not isinstance(kind, str) or kind not in known:  # a list or object is no type name
        names = ", ".join(listed or known)
        raise StudyError(src, f"{fld}.type", f"{kind!r} is not a {what}; known: {names}")
    return raw, str(kind)
