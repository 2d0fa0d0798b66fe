"""The verdict on the final residual: ``explained`` or ``unexplained_residual`` with its
size, where it sits and its sentence."""

from __future__ import annotations

from typing import Any

from ..residual import RunResidual, gap
from .localise import excess_location
from .noise_floor import NoiseFloor
from .significance import Gate, excess
from .timeaxis import time_axis, trend_text


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
