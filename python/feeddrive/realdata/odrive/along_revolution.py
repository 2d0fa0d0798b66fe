"""Periodic or not along the revolution: the rectangular-window DSTFT of a map, compared with
the same transform of its constant line model."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import signal

from .recordings import COUNTS_PER_REV, CoggingMap
from .spectrum import revolution_spectrum, synthesise

WINDOW_COUNTS = COUNTS_PER_REV // 2  # shortest window separating 12/rev from 14/rev (1/W = 2/rev)
N_WINDOW_POSITIONS = 64
PERIODIC_TOL = 0.25  # max |DSTFT - constant-line DSTFT| / line amplitude for "periodic";
# the repeatable sweeps a, b, c, d, e stay <= 0.14 on all tracked lines


@dataclass(frozen=True)
class PositionSpectrum:
    """Short-time spectrum along the revolution: ``amplitude[q, j]`` is the complex amplitude of
    order q in the window centred at ``centres[j]`` [counts], demodulated so that a line of
    constant amplitude and phase gives the same value at every centre."""

    centres: np.ndarray
    orders: np.ndarray
    amplitude: np.ndarray


def position_stft(
    values: np.ndarray, counts: np.ndarray, window_counts: int = WINDOW_COUNTS
) -> PositionSpectrum:
    """Rectangular-window DSTFT of a map sampled on a uniform grid over one revolution.

    The map is periodic, so the windows wrap around the revolution (the data are tiled).
    """
    n = values.size
    step = COUNTS_PER_REV // n
    if counts.size != n or n * step != COUNTS_PER_REV or np.any(np.diff(counts) != step):
        raise ValueError(
            f"map of {n} points on counts {counts[:2]}... is not a uniform revolution grid"
        )
    width = window_counts // step
    sft = signal.ShortTimeFFT(np.ones(width), hop=max(n // N_WINDOW_POSITIONS, 1), fs=n, mfft=n)
    x = np.tile(values, 3)
    s = sft.stft(x)
    centre = np.rint(sft.t(x.size) * n).astype(int)  # t is in revolutions
    keep = (centre >= n) & (centre < 2 * n)
    centres = counts[0] + step * (centre[keep] - n)
    q = np.rint(sft.f).astype(int)
    scale = np.where(q == 0, 1.0, 2.0)[:, None] / width
    demod = np.exp(-2j * np.pi * np.outer(q, centres) / COUNTS_PER_REV)
    return PositionSpectrum(centres, q, s[:, keep] * scale * demod)


@dataclass(frozen=True)
class LineTrack:
    """One line along the revolution: DSTFT magnitude range, the range the constant line model
    gives through the same window (leakage), and the largest departure from that model
    relative to the full-revolution amplitude."""

    order: int
    amplitude: float
    dstft_range: tuple[float, float]
    model_range: tuple[float, float]
    deviation: float

    @property
    def periodic(self) -> bool:
        return self.deviation <= PERIODIC_TOL


@dataclass(frozen=True)
class Stationarity:
    """Periodic / not periodic along the revolution for one map (window: half a revolution)."""

    map_name: str
    tracks: tuple[LineTrack, ...]
    local_mean_range: tuple[float, float]  # zero-frequency term of the DSTFT [A]
    local_mean_drift: float  # its peak-to-peak not reproduced by the line model [A]
    residual_rms: float  # rms of map minus constant line model [A]


def stationarity(m: CoggingMap, lines: np.ndarray, orders: tuple[int, ...]) -> Stationarity:
    """Track ``orders`` and the zero-frequency term of map ``m`` along the revolution.

    The constant line model holds the orders ``lines`` (the reference map's lines) with this
    map's own amplitudes and phases; it is passed through the same window, so its leakage is
    not mistaken for variation.  A line whose amplitude or phase wanders along the revolution
    spreads into neighbouring orders (sidebands) that the model does not hold.
    """
    spec = revolution_spectrum(m)
    model = synthesise(spec, lines, m.counts)
    meas, mod = position_stft(m.current, m.counts), position_stft(model, m.counts)
    tracks = []
    for q in orders:
        a, b = meas.amplitude[q], mod.amplitude[q]
        tracks.append(
            LineTrack(
                int(q),
                float(abs(spec[q])),
                _range(np.abs(a)),
                _range(np.abs(b)),
                float(np.max(np.abs(a - b)) / abs(spec[q])),
            )
        )
    dc = meas.amplitude[0].real
    return Stationarity(
        m.name,
        tuple(tracks),
        _range(dc),
        float(np.ptp(dc - mod.amplitude[0].real)),
        float(np.std(m.current - model)),
    )


def _range(v: np.ndarray) -> tuple[float, float]:
    return float(np.min(v)), float(np.max(v))
