"""Reading a controller spec: a key's finite number, the keys a type allows and the
computation delay every type takes."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

#: keys every type's spec may have: ``delay`` (0 or 1 sample of computation delay)
COMMON_KEYS = frozenset({"delay"})


def spec_number(spec: Mapping[str, Any], key: str, default: Any = None) -> float:
    """The finite number under ``key`` (``default`` when absent and given); ValueError else."""
    if key not in spec:
        if default is None:
            raise ValueError(f"controller ({spec.get('type')}): key {key!r} missing")
        return float(default)
    v = spec[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v):
        raise ValueError(f"controller ({spec.get('type')}): {key} = {v!r} is not a finite number")
    return float(v)


def check_keys(spec: Mapping[str, Any], allowed: set[str]) -> None:
    """ValueError naming the keys of ``spec`` outside ``allowed``, ``type`` and COMMON_KEYS."""
    unknown = set(spec) - allowed - {"type"} - COMMON_KEYS
    if unknown:
        raise ValueError(
            f"controller ({spec.get('type')}): unknown key(s) {sorted(unknown)}; "
            f"allowed {sorted(allowed)}"
        )


def spec_delay(spec: Mapping[str, Any]) -> int:
    """The spec's computation delay [samples]: 0 (default) or 1; ValueError otherwise."""
    d = spec.get("delay", 0)
    if isinstance(d, bool) or d not in (0, 1):
        raise ValueError(f"controller ({spec.get('type')}): delay = {d!r}: allowed 0 or 1 sample")
    return int(d)
