"""Stability margins of a sampled SISO loop, computed numerically from its frequency response.

The loop transfer function L(z) is taken with the negative-feedback convention: the closed
loop is stable-margin-critical where L = -1.  Gain margins are measured at the phase
crossovers (L real and negative) and split into the upper margin (|L| < 1 there: how much
the gain may grow) and the lower margin (|L| > 1 there: how much it may shrink, present for
conditionally stable loops such as a double integrator with integral action).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Margins:
    """Loop margins.

    gain_margin_db : smallest upper gain margin [dB] (inf if none).
    gain_margin_hz : frequency of that phase crossover [Hz].
    lower_gain_margin_db : smallest gain-reduction margin [dB, <= 0] (-inf if none).
    lower_gain_margin_hz : its frequency [Hz].
    phase_margin_deg : smallest phase margin over the gain crossovers [deg].
    crossover_hz : gain-crossover frequency of that phase margin [Hz].
    modulus_margin : min |1 + L| (distance of the Nyquist curve from -1).
    """

    gain_margin_db: float
    gain_margin_hz: float
    lower_gain_margin_db: float
    lower_gain_margin_hz: float
    phase_margin_deg: float
    crossover_hz: float
    modulus_margin: float

    def as_dict(self) -> dict[str, float]:
        """Plain dict of the fields."""
        return dict(self.__dict__)


def _crossings(f: np.ndarray, g: np.ndarray) -> list[tuple[float, int, float]]:
    """Linear-interpolated zero crossings of g(f): (frequency, index, fraction)."""
    out = []
    s = np.sign(g)
    idx = np.nonzero(s[:-1] * s[1:] < 0)[0]
    for i in idx:
        t = g[i] / (g[i] - g[i + 1])
        out.append((f[i] + t * (f[i + 1] - f[i]), int(i), float(t)))
    for i in np.nonzero(g == 0.0)[0]:
        out.append((f[i], int(i), 0.0))
    return out


def loop_margins(f: np.ndarray, L: np.ndarray) -> Margins:
    """Margins from the loop frequency response ``L`` sampled at increasing frequencies ``f`` [Hz].

    The grid should be dense (log-spaced, thousands of points) and reach the Nyquist
    frequency, where a sampled loop is real.
    """
    f = np.asarray(f, dtype=float)
    L = np.asarray(L, dtype=complex)
    mag = np.abs(L)
    gm, gm_f, lgm, lgm_f = np.inf, np.nan, -np.inf, np.nan
    for fc, i, t in _crossings(f, L.imag):
        re = L.real[i] + t * (L.real[i + 1] - L.real[i]) if i + 1 < len(f) else L.real[i]
        if re >= 0:
            continue
        m_db = -20.0 * np.log10(-re)
        if m_db >= 0 and m_db < gm:
            gm, gm_f = m_db, fc
        elif m_db < 0 and m_db > lgm:
            lgm, lgm_f = m_db, fc
    # Nyquist end point: L is real there
    if abs(L[-1].imag) <= 1e-9 * max(mag[-1], 1e-300) and L[-1].real < 0:
        m_db = -20.0 * np.log10(-L[-1].real)
        if 0 <= m_db < gm:
            gm, gm_f = m_db, f[-1]
    pm, pm_f = np.inf, np.nan
    for fc, i, t in _crossings(f, np.log(mag)):
        j = min(i + 1, len(f) - 1)
        Lc = L[i] + t * (L[j] - L[i])
        p = 180.0 - abs(np.degrees(np.angle(Lc)))  # angular distance of L from -1
        if p < pm:
            pm, pm_f = p, fc
    return Margins(
        gain_margin_db=float(gm),
        gain_margin_hz=float(gm_f),
        lower_gain_margin_db=float(lgm),
        lower_gain_margin_hz=float(lgm_f),
        phase_margin_deg=float(pm),
        crossover_hz=float(pm_f),
        modulus_margin=float(np.min(np.abs(1.0 + L))),
    )


def frequency_grid(Ts: float, f_min: float = 0.01, n: int = 20000) -> np.ndarray:
    """Log-spaced grid from ``f_min`` to just below the Nyquist frequency, plus Nyquist [Hz]."""
    f_nyq = 0.5 / Ts
    return np.concatenate((np.logspace(np.log10(f_min), np.log10(f_nyq * 0.99999), n - 1), [f_nyq]))


#: margins below which a loop is called poorly damped: gain 6 dB, phase 30 deg, |1 + L| 0.5
POOR_GAIN_DB, POOR_PHASE_DEG, POOR_MODULUS = 6.0, 30.0, 0.5


def poor_margins(m: Margins) -> list[str]:
    """What is poor in ``m`` (empty when every margin meets :data:`POOR_GAIN_DB`,
    :data:`POOR_PHASE_DEG`, :data:`POOR_MODULUS`), one phrase each."""
    out = []
    if m.gain_margin_db < POOR_GAIN_DB:
        out.append(
            f"gain margin {m.gain_margin_db:.1f} dB < {POOR_GAIN_DB:g} dB "
            f"(at {m.gain_margin_hz:.0f} Hz)"
        )
    if m.phase_margin_deg < POOR_PHASE_DEG:
        out.append(
            f"phase margin {m.phase_margin_deg:.1f} deg < {POOR_PHASE_DEG:g} deg "
            f"(crossover {m.crossover_hz:.0f} Hz)"
        )
    if m.modulus_margin < POOR_MODULUS:
        out.append(f"modulus margin {m.modulus_margin:.2f} < {POOR_MODULUS:g}")
    return out
