"""Compliance (effect ``compliance``, beyond the paper): a load m2 on a spring-damper on the slide.

C twin: fmu_src/compliance.c.  The slide (motor force, cogging, friction) carries a second
mass m2 through a spring k2 and a damper c2::

    m a   = F_slide + k2 q + c2 w,        q = x_load - x,  w = v_load - v,
    m2 a2 = -(k2 q + c2 w),               dq/dt = w,  dw/dt = a2 - a,

with ``k2 = m2 (2 pi f)^2`` and ``c2 = 2 zeta m2 (2 pi f)``: ``f`` [Hz] is the natural
frequency of the load on its spring with the slide held (the anti-resonance of the
motor-side response), ``zeta`` [1] its damping ratio.  With the slide free the coupled mode
lies at ``f sqrt(1 + m2/m)``.  The encoder reads the slide (``sensor_side`` 0, default) or
the load (1).

Along a measured slide motion the load is a second-order filter of the slide's
acceleration: ``a2 = H(s) a`` with ``H(s) = (2 zeta w s + w^2) / (s^2 + 2 zeta w s + w^2)``;
the force the load puts on the slide is ``-m2 a2`` (:func:`load_acceleration`), which is what
identification and diagnosis regress on.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.signal import cont2discrete, lfilter

#: The FMU's range of compliance.f [Hz] (modelDescription.xml).
F_RANGE = (20.0, 200.0)


@dataclass(frozen=True)
class Compliance:
    """The compiled compliance (params.c ``compile_compliance``); ``on`` False: no load."""

    on: bool
    m2: float          #: [kg]
    f: float           #: [Hz]
    zeta: float        #: [1]
    sensor_side: int   #: 0 motor slide, 1 load

    @property
    def omega(self) -> float:
        """2 pi f [rad/s]."""
        return 2.0 * math.pi * self.f

    @property
    def k2(self) -> float:
        """Spring stiffness m2 (2 pi f)^2 [N/m]."""
        w = 2.0 * math.pi * self.f
        return self.m2 * w * w

    @property
    def c2(self) -> float:
        """Damper 2 zeta m2 (2 pi f) [N s/m]."""
        return 2.0 * self.zeta * self.m2 * (2.0 * math.pi * self.f)

    @classmethod
    def from_parameters(cls, val: Mapping[str, Any]) -> "Compliance":
        """From FMU-named values (``effects.compliance``, ``compliance.*``)."""
        return cls(on=bool(val["effects.compliance"]), m2=float(val["compliance.m2"]),
                   f=float(val["compliance.f"]), zeta=float(val["compliance.zeta"]),
                   sensor_side=int(val["compliance.sensor_side"]))

    def force(self, q: ArrayLike, w: ArrayLike) -> np.ndarray:
        """k2 q + c2 w [N]: the load's force on the slide (0 when off)."""
        if not self.on:
            return np.zeros_like(np.asarray(q, dtype=float))
        return self.k2 * np.asarray(q, dtype=float) + self.c2 * np.asarray(w, dtype=float)

    def derivatives(self, q: ArrayLike, w: ArrayLike, a: ArrayLike
                    ) -> tuple[np.ndarray, np.ndarray]:
        """(dq/dt, dw/dt) given the slide's acceleration a (zeros when off)."""
        q, w, a = (np.asarray(z, dtype=float) for z in (q, w, a))
        if not self.on:
            return np.zeros_like(q), np.zeros_like(w)
        return w.copy(), -self.force(q, w) / self.m2 - a


def load_filter(f: float, zeta: float, Ts: float) -> tuple[np.ndarray, np.ndarray]:
    """(b, a) of H(s) = (2 zeta w s + w^2) / (s^2 + 2 zeta w s + w^2), w = 2 pi f, discretised
    with a first-order hold at ``Ts`` (the input taken as linear between samples)."""
    if not (f > 0 and zeta >= 0 and Ts > 0):
        raise ValueError(f"load_filter: f = {f!r} Hz, zeta = {zeta!r}, Ts = {Ts!r} s: allowed "
                         "f > 0, zeta >= 0, Ts > 0")
    w = 2.0 * math.pi * f
    b, a, _ = cont2discrete(([2.0 * zeta * w, w * w], [1.0, 2.0 * zeta * w, w * w]), Ts,
                            method="foh")
    return np.atleast_1d(np.squeeze(b)), np.asarray(a, dtype=float)


def load_acceleration(a: ArrayLike, Ts: float, f: float, zeta: float) -> np.ndarray:
    """The load's acceleration a2 = H(s) a along a sampled slide acceleration ``a`` [m/s^2],
    from rest (the load relaxed on its spring at the first sample; NaN samples count as 0)."""
    b, den = load_filter(f, zeta, Ts)
    return lfilter(b, den, np.nan_to_num(np.asarray(a, dtype=float)))
