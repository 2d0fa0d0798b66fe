"""Zero-phase-error tracking pre-filter (Tomizuka 1987) for a closed loop r -> y.

For a closed loop T(z) = b0 B_a(z) B_u(z) / A_c(z) (degree n of A_c, B_a monic with the
acceptable zeros, B_u monic with the unacceptable ones, s = deg B_u), the pre-filter

    F(z) = A_c(z) B_u(z^-1) / (b0 B_a(z) B_u(1)^2)

gives F T = B_u(z) B_u(z^-1) / B_u(1)^2, real and positive on the unit circle: zero phase,
unit DC gain, gain error only near the unacceptable zeros' frequencies.  F is non-causal by
n - deg B_a = d + s samples (d the relative degree of T): applied to a whole reference array
it is run as a causal filter and the output advanced by that preview.

Acceptable (cancelled) zeros: inside the unit circle, and if Re z < 0 also |z| < ``radius``
(default 0.9).  Tomizuka cancels every zero inside the unit circle; zeros on it (the ZOH
sampling zero z = -1 of the double integrator) or outside are unacceptable, and so are
oscillatory zeros near -1, whose cancellation would ring at the Nyquist frequency.  Slow
zeros near +1 (from the PI part of the loop) must be cancelled: kept in B_u they would give
the filter a huge high-frequency gain (B_u(1) ~ 0).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal

UNIT_CIRCLE_TOL = 1e-6  #: zeros this close to the unit circle count as on it


class ZPETC:
    """ZPETC pre-filter for T(z) = num(z)/den(z) (descending powers of z).

    Attributes
    ----------
    preview : samples of preview d + s (the filter needs x_ref that far ahead).
    zeros_cancelled, zeros_kept : the acceptable / unacceptable zeros of T.
    b, a : causal filter coefficients (powers of z^-1) applied before the advance.
    """

    def __init__(self, num: ArrayLike, den: ArrayLike, radius: float = 0.9) -> None:
        nz = np.trim_zeros(np.atleast_1d(np.asarray(num, dtype=float)), "f")
        dz = np.trim_zeros(np.atleast_1d(np.asarray(den, dtype=float)), "f")
        if nz.size == 0 or dz.size == 0:
            raise ValueError("zpetc.py: empty numerator or denominator")
        if len(nz) > len(dz):
            raise ValueError("zpetc.py: T(z) must be proper (deg num <= deg den)")
        poles = np.roots(dz)
        if np.any(np.abs(poles) >= 1.0):
            raise ValueError(f"zpetc.py: the closed loop is unstable (poles {poles})")
        nz, dz = nz / dz[0], dz / dz[0]
        b0 = nz[0]
        zeros = np.roots(nz)
        inside = np.abs(zeros) < 1.0 - UNIT_CIRCLE_TOL
        acc = inside & ((zeros.real >= 0) | (np.abs(zeros) < radius))
        self.zeros_cancelled = zeros[acc]
        self.zeros_kept = zeros[~acc]
        Ba = np.atleast_1d(np.real(np.poly(self.zeros_cancelled)))
        Bu = np.atleast_1d(np.real(np.poly(self.zeros_kept)))
        Bu1 = np.polyval(Bu, 1.0)
        if abs(Bu1) < 1e-12:
            raise ValueError("zpetc.py: T(z) has a zero at z = 1, no tracking possible")
        n, na, s = len(dz) - 1, len(Ba) - 1, len(Bu) - 1
        self.preview = n - na  #: d + s samples
        self.relative_degree = n - na - s
        # causal form: [A_c(z) z^-n][B_u(z^-1)] / (b0 B_u(1)^2 [B_a(z) z^-na])
        self.b = np.convolve(dz, Bu[::-1]) / (b0 * Bu1**2)
        self.a = Ba
        self.num, self.den, self.radius = nz, dz, radius

    @classmethod
    def from_controller(cls, controller: Any, radius: float = 0.9) -> ZPETC:
        """Pre-filter for a controller exposing ``closed_loop_tf() -> (num, den)``."""
        num, den = controller.closed_loop_tf()
        return cls(num, den, radius=radius)

    def filter(self, x_ref: ArrayLike) -> np.ndarray:
        """x_cmd such that the closed loop's output follows ``x_ref`` with zero phase error.

        The reference is taken as constant (x_ref[0]) before its start and constant
        (x_ref[-1]) for the ``preview`` samples after its end.
        """
        x = np.asarray(x_ref, dtype=float)
        if x.ndim != 1 or x.size == 0:
            raise ValueError("zpetc.py: x_ref must be a non-empty 1-D array")
        xp = np.concatenate((x, np.full(self.preview, x[-1])))
        zi = signal.lfilter_zi(self.b, self.a) * x[0]
        y, _ = signal.lfilter(self.b, self.a, xp, zi=zi)
        return y[self.preview : self.preview + len(x)]

    def tracking_response(self, f: ArrayLike, Ts: float) -> np.ndarray:
        """F(z) T(z) at frequencies ``f`` [Hz] (real, = B_u B_u* / B_u(1)^2)."""
        z = np.exp(1j * 2 * np.pi * np.asarray(f, dtype=float) * Ts)
        F = np.polyval(self.b[::-1], 1 / z) / np.polyval(self.a[::-1], 1 / z) * z**self.preview
        return F * np.polyval(self.num, z) / np.polyval(self.den, z)
