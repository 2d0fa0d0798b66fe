"""What a diagnosis step changes: the parameters with their SI units and relative change,
and the force the change makes along the runs."""

from __future__ import annotations

import numpy as np

from ..model_file import ModelFile
from ..residual import RunResidual

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
