"""Friction from forward minus reverse holding-current maps, with the direction-dependent
rest-position offset and the white noise of the difference."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .recordings import COUNTS_PER_REV, FORWARD_16, REVERSE_16, CoggingMap
from .spectrum import Line, revolution_spectrum, top_lines


@dataclass(frozen=True)
class FrictionFindings:
    """Forward minus reverse holding current (= 2 x friction / Kt)."""

    forward: str  # matched pair: same crosstalk line in both maps
    reverse: str
    mean_difference: float  # [A]
    pair_means: tuple[float, float, float]  # min, mean, max over all forward x reverse pairs [A]
    difference_std: float  # position-dependent part of the matched pair [A]
    difference_lines: tuple[Line, ...]
    offset_counts: float  # fitted direction-dependent position offset (fwd - rev) [counts]
    offset_r2: float  # share of the difference variance it explains
    residual_std: float  # what is left [A]
    noise_std: float  # white point-to-point noise of the difference, from the
    # orders above 1/4 of the grid rate (no lines there) [A]


def friction(maps: dict[str, CoggingMap], crosstalk_order: int) -> FrictionFindings:
    """Forward/reverse difference; the matched pair has the closest crosstalk line, so the
    neighbour-dependent 7/rev part cancels and what remains is friction and hysteresis."""
    spec = {k: revolution_spectrum(maps[k]) for k in FORWARD_16 + REVERSE_16}
    means = [
        maps[f].current.mean() - maps[r].current.mean() for f in FORWARD_16 for r in REVERSE_16
    ]
    fwd, rev = min(
        ((f, r) for f in FORWARD_16 for r in REVERSE_16),
        key=lambda p: abs(spec[p[0]][crosstalk_order] - spec[p[1]][crosstalk_order]),
    )
    f, r = maps[fwd], maps[rev]
    r_on_f = np.interp(f.counts, r.counts, r.current, period=COUNTS_PER_REV)
    d = f.current - r_on_f
    # direction-dependent rest position: I_f(x) - I_r(x) ~ D + s dI/dx (spectral derivative)
    mean_map = np.fft.rfft(0.5 * (f.current + r_on_f))
    k = np.arange(mean_map.size)
    slope = np.fft.irfft(mean_map * 2j * np.pi * k / COUNTS_PER_REV, f.current.size)
    coef, *_ = np.linalg.lstsq(np.column_stack([np.ones_like(d), slope]), d, rcond=None)
    res = d - coef[0] - coef[1] * slope
    dspec = np.fft.rfft(d) / d.size
    dspec[1:] *= 2.0
    hi = np.abs(dspec[dspec.size // 2 : -1])
    return FrictionFindings(
        fwd,
        rev,
        float(d.mean()),
        (float(min(means)), float(np.mean(means)), float(max(means))),
        float(d.std()),
        top_lines(dspec, 4),
        float(coef[1]),
        float(1.0 - res.var() / d.var()),
        float(res.std()),
        float(np.sqrt(np.sum(hi**2))),
    )
