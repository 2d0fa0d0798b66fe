"""The full-revolution line spectrum of a map: its lines, the orders above the noise floor
and the constant line model."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .recordings import COUNTS_PER_REV, CoggingMap

N_LINES = 5  # lines reported (the README quotes five)
LINE_FLOOR = 10.0  # a line: amplitude >= LINE_FLOOR x median amplitude of all orders;
# in a_16 this keeps only multiples of 7 or 12 (0.031 A floor)


@dataclass(frozen=True)
class Line:
    """Spectral line: I(x) contains amplitude*cos(2 pi order x / 8192 + phase)."""

    order: int
    amplitude: float
    phase_deg: float


def revolution_spectrum(m: CoggingMap) -> np.ndarray:
    """Complex amplitudes c_k, k = 0..n/2, with I(x) = Re sum_k c_k exp(2j pi k x / 8192).

    The phase is referred to count 0 whatever the grid offset (reverse sweeps start at 15).
    """
    n = m.current.size
    c = np.fft.rfft(m.current) / n
    c[1:] *= 2.0
    if n % 2 == 0:
        c[-1] /= 2.0
    k = np.arange(c.size)
    return c * np.exp(-2j * np.pi * k * m.counts[0] / COUNTS_PER_REV)


def top_lines(spec: np.ndarray, count: int = N_LINES) -> tuple[Line, ...]:
    """The ``count`` largest lines (order >= 1), largest first."""
    orders = np.argsort(np.abs(spec[1:]))[::-1][:count] + 1
    return tuple(line_of(spec, int(k)) for k in orders)


def line_of(spec: np.ndarray, k: int) -> Line:
    return Line(k, float(abs(spec[k])), float(np.degrees(np.angle(spec[k]))))


def line_orders(spec: np.ndarray) -> np.ndarray:
    """Orders whose amplitude is >= LINE_FLOOR x the median amplitude (robust noise floor)."""
    amp = np.abs(spec[1:])
    return np.flatnonzero(amp >= LINE_FLOOR * np.median(amp)) + 1


def synthesise(spec: np.ndarray, orders: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Constant line model: mean plus the given orders of ``spec``, evaluated at ``counts``."""
    ph = 2j * np.pi * np.outer(counts, orders) / COUNTS_PER_REV
    return spec[0].real + (np.exp(ph) @ spec[orders]).real


def family(order: int, n_orders: int) -> np.ndarray:
    """Odd multiples of ``order`` below ``n_orders`` (a field shifted by half its period flips them)."""
    return np.arange(order, n_orders, 2 * order)
