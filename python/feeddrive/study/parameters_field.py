"""A study file's ``parameters`` (how each FMU parameter varies) and its ``design`` (which
runs are made of them)."""

from __future__ import annotations

import math
from typing import Any

import scipy.stats

from ..model_file import PARAMETER_NAMES
from .fields import StudyError, integer_field, number_field, object_field, typed_object_field
from .spec import ParameterSpec

DESIGNS = ("grid", "lhs", "monte_carlo", "oat")


def parameter_field(name: str, raw: Any, base: float, src: str) -> ParameterSpec:
    """How parameter ``name`` (model value ``base``) varies: a range, ``relative``, a
    distribution of scipy.stats or values."""
    fld = f"parameters[{name!r}]"
    if name not in PARAMETER_NAMES:
        raise StudyError(src, fld, "not a parameter of the model file format")
    raw = object_field(raw, src, fld)
    kinds = [k for k in ("low", "relative", "distribution", "values") if k in raw]
    if len(kinds) != 1:
        raise StudyError(src, fld, "give exactly one of low/high, relative, distribution, values")
    kind = kinds[0]
    if kind == "low":
        object_field(raw, src, fld, ("low", "high"))
        if "high" not in raw:
            raise StudyError(src, f"{fld}.high", "missing (a range needs low and high)")
        lo, hi = (
            number_field(raw["low"], src, f"{fld}.low"),
            number_field(raw["high"], src, f"{fld}.high"),
        )
        if not hi > lo:
            raise StudyError(src, f"{fld}.high", f"must be > low ({lo}), got {hi}")
        return ParameterSpec(name, base, low=lo, high=hi)
    if kind == "relative":
        object_field(raw, src, fld, ("relative",))
        r = number_field(raw["relative"], src, f"{fld}.relative", positive=True)
        lo, hi = sorted((base * (1 - r), base * (1 + r)))
        if not hi > lo:
            raise StudyError(src, f"{fld}.relative", f"the base value is {base}: no range")
        return ParameterSpec(name, base, low=lo, high=hi)
    if kind == "values":
        object_field(raw, src, fld, ("values",))
        vals = raw["values"]
        if not isinstance(vals, list) or not vals:
            raise StudyError(src, f"{fld}.values", f"must be a non-empty list, got {vals!r}")
        return ParameterSpec(
            name,
            base,
            values=tuple(number_field(v, src, f"{fld}.values[{j}]") for j, v in enumerate(vals)),
        )
    dist = raw["distribution"]
    cls = getattr(scipy.stats, dist, None) if isinstance(dist, str) else None
    if not isinstance(cls, scipy.stats.rv_continuous):
        raise StudyError(
            src, f"{fld}.distribution", f"{dist!r} is not a continuous distribution of scipy.stats"
        )
    args = {k: number_field(v, src, f"{fld}.{k}") for k, v in raw.items() if k != "distribution"}
    try:
        frozen = cls(**args)
        ok = math.isfinite(float(frozen.ppf(0.5)))
    except (TypeError, ValueError) as e:
        raise StudyError(src, fld, f"scipy.stats.{dist}({args}): {e}") from None
    if not ok:
        raise StudyError(src, fld, f"scipy.stats.{dist}({args}) has invalid arguments")
    return ParameterSpec(name, base, distribution=dist, dist_args=args)


def design_field(raw: Any, src: str, params: tuple[ParameterSpec, ...]) -> dict[str, Any]:
    """The study's ``design``, checked against what its ``params`` give."""
    raw, kind = typed_object_field(raw, src, "design", DESIGNS, "design")
    allowed = {
        "grid": ("type", "levels"),
        "lhs": ("type", "runs", "seed"),
        "monte_carlo": ("type", "runs", "seed"),
        "oat": ("type",),
    }[kind]
    object_field(raw, src, "design", allowed)
    out: dict[str, Any] = {"type": kind}
    if kind == "grid":
        out["levels"] = integer_field(raw.get("levels", 3), src, "design.levels", minimum=2)
        bad = [p for p in params if p.distribution is not None]
    else:
        if kind != "oat":
            out["runs"] = integer_field(raw.get("runs"), src, "design.runs")
            out["seed"] = integer_field(raw.get("seed", 0), src, "design.seed", minimum=0)
        need_range = kind == "oat"
        bad = [p for p in params if p.values is not None or (need_range and p.low is None)]
    if bad:
        raise StudyError(
            src,
            f"parameters[{bad[0].name!r}]",
            f"cannot be used by a {kind} design (grid: ranges or values; lhs, "
            f"monte_carlo: ranges or distributions; oat: ranges)",
        )
    return out
