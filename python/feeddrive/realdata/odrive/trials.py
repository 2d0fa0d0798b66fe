"""Repeated forward maps against the reference map: correlation as measured and shifted by
half a turn, the crosstalk line of each trial, and the best circular alignment."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .recordings import CoggingMap
from .spectrum import Line, line_of, revolution_spectrum


@dataclass(frozen=True)
class TrialComparison:
    """A repeated forward map against the reference map."""

    name: str
    correlation: float  # as measured
    correlation_half_turn: float  # trial rolled by 4096 counts
    rms_difference: float  # after the better of the two alignments [A]
    crosstalk: Line  # the crosstalk line of this trial (phase vs count 0)
    odd_coherence: float  # +1: odd non-crosstalk orders as in the reference; -1: half-turn shift


def compare_trial(ref: CoggingMap, m: CoggingMap, crosstalk_order: int) -> TrialComparison:
    """Correlate ``m`` with ``ref`` as measured and shifted by half a turn; test which fits the
    odd orders that are not crosstalk (a half-turn shift flips every odd order)."""
    if not np.array_equal(ref.counts, m.counts):
        raise ValueError(f"{m.name}: grid differs from {ref.name}")
    half = np.roll(m.current, m.current.size // 2)
    r0, r1 = np.corrcoef(ref.current, m.current)[0, 1], np.corrcoef(ref.current, half)[0, 1]
    d = ref.current - (m.current if r0 >= r1 else half)
    sr, sm = revolution_spectrum(ref), revolution_spectrum(m)
    k = np.array([j for j in range(1, sr.size - 1, 2) if j % crosstalk_order])
    coh = np.sum((sm[k] * np.conj(sr[k])).real) / np.sum(np.abs(sr[k]) ** 2)
    return TrialComparison(
        m.name,
        float(r0),
        float(r1),
        float(np.std(d - d.mean())),
        line_of(sm, crosstalk_order),
        float(coh),
    )


def best_shift(ref: CoggingMap, m: CoggingMap) -> tuple[int, float]:
    """Circular shift [counts] that best aligns ``m`` with ``ref`` (same grid), and its correlation."""
    a, b = ref.current - ref.current.mean(), m.current - m.current.mean()
    xc = np.fft.irfft(np.fft.rfft(a) * np.conj(np.fft.rfft(b)), a.size)  # xc[s] = a . roll(b, s)
    s = int(np.argmax(xc))
    return s * m.step, float(xc[s] / np.sqrt(a @ a * (b @ b)))
