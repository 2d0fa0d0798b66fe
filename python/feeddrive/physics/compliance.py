"""Compliance (effect ``compliance``, beyond the paper): a load m2 on a spring-damper on the slide.

C twin: fmu_src/physics/compliance.c.  The slide (motor force, cogging, friction) carries a second
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
from scipy.signal import lfilter, lfilter_zi

from ..effects import Structure, structure_on

#: The FMU's range of compliance.f [Hz] (modelDescription.xml).
F_RANGE = (20.0, 200.0)


@dataclass(frozen=True)
class Compliance:
    """The compiled compliance (compliance.c ``compile_compliance``); ``on`` False: no load."""

    on: bool
    m2: float  #: [kg]
    f: float  #: [Hz]
    zeta: float  #: [1]
    sensor_side: int  #: 0 motor slide, 1 load

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
    def from_parameters(cls, val: Mapping[str, Any]) -> Compliance:
        """From FMU-named values (``compliance.*`` and the switch that selects the plant
        structure :attr:`~feeddrive.effects.Structure.LOAD_ON_SPRING`)."""
        return cls(
            on=structure_on(val, Structure.LOAD_ON_SPRING),
            m2=float(val["compliance.m2"]),
            f=float(val["compliance.f"]),
            zeta=float(val["compliance.zeta"]),
            sensor_side=int(val["compliance.sensor_side"]),
        )

    def force(self, q: ArrayLike, w: ArrayLike) -> np.ndarray:
        """k2 q + c2 w [N]: the load's force on the slide (0 when off)."""
        if not self.on:
            return np.zeros_like(np.asarray(q, dtype=float))
        return self.k2 * np.asarray(q, dtype=float) + self.c2 * np.asarray(w, dtype=float)

    def derivatives(
        self, q: ArrayLike, w: ArrayLike, a: ArrayLike
    ) -> tuple[np.ndarray, np.ndarray]:
        """(dq/dt, dw/dt) given the slide's acceleration a (zeros when off)."""
        q, w, a = (np.asarray(z, dtype=float) for z in (q, w, a))
        if not self.on:
            return np.zeros_like(q), np.zeros_like(w)
        return w.copy(), -self.force(q, w) / self.m2 - a


def _expm4(M: np.ndarray) -> np.ndarray:
    """exp(M) of the small block matrix of :func:`load_filter` by scaling and squaring with an
    18-term Taylor series (relative error ~1e-16 at the norms met here).  scipy.linalg.expm
    costs milliseconds per call on a loaded machine; the search needs hundreds of calls."""
    nrm = float(np.abs(M).sum(axis=1).max())
    k = max(0, int(math.ceil(math.log2(nrm))) + 1) if nrm > 0.5 else 0
    A = M / (2.0**k)
    E = np.eye(len(M))
    T = np.eye(len(M))
    for j in range(1, 19):
        T = T @ A / j
        E = E + T
    for _ in range(k):
        E = E @ E
    return E


def load_filter(f: float, zeta: float, Ts: float) -> tuple[np.ndarray, np.ndarray]:
    """(b, a) of H(s) = (2 zeta w s + w^2) / (s^2 + 2 zeta w s + w^2), w = 2 pi f, discretised
    with a first-order hold at ``Ts`` (the input linear between samples; the construction of
    ``scipy.signal.cont2discrete(method='foh')``, written out for the 2-state system)."""
    if not (f > 0 and zeta >= 0 and Ts > 0):
        raise ValueError(
            f"load_filter: f = {f!r} Hz, zeta = {zeta!r}, Ts = {Ts!r} s: allowed "
            "f > 0, zeta >= 0, Ts > 0"
        )
    w = 2.0 * math.pi * f
    em = np.zeros((4, 4))
    em[0, 1] = 1.0
    em[1, 0], em[1, 1], em[1, 2] = -w * w, -2.0 * zeta * w, 1.0
    em *= Ts
    em[2, 3] = 1.0
    ms = _expm4(em)
    Ad, B1, B3 = ms[:2, :2], ms[:2, 2], ms[:2, 3]
    Bd = B1 - B3 + Ad @ B3
    C = np.array([w * w, 2.0 * zeta * w])
    dd = float(C @ B3)
    tr, det = Ad[0, 0] + Ad[1, 1], Ad[0, 0] * Ad[1, 1] - Ad[0, 1] * Ad[1, 0]
    den = np.array([1.0, -tr, det])
    c0 = (
        -C[0] * Ad[1, 1] * Bd[0]
        + C[0] * Ad[0, 1] * Bd[1]
        + C[1] * Ad[1, 0] * Bd[0]
        - C[1] * Ad[0, 0] * Bd[1]
    )
    num = dd * den + np.array([0.0, float(C @ Bd), c0])
    return num, den


def load_acceleration(a: ArrayLike, Ts: float, f: float, zeta: float) -> np.ndarray:
    """The load's acceleration a2 = H(s) a along a sampled slide acceleration ``a`` [m/s^2].

    The filter starts at the first finite sample in steady state for the acceleration there
    (the load moving with the slide, H(0) = 1: a relaxed spring when the slide is at rest or
    at constant speed); NaN samples before it give NaN, later NaN samples count as 0.  A
    start from rest with a non-zero first acceleration would instead ring at f for
    1 / (2 pi zeta f) seconds, a transient the measurement does not hold.
    """
    a = np.asarray(a, dtype=float)
    out = np.full(a.shape, np.nan)
    fin = np.flatnonzero(np.isfinite(a))
    if fin.size == 0:
        return out
    k0 = int(fin[0])
    seg = np.nan_to_num(a[k0:])
    b, den = load_filter(f, zeta, Ts)
    zi = lfilter_zi(b, den) * seg[0]
    out[k0:] = lfilter(b, den, seg, zi=zi)[0]
    return out


def load_free_response(a: ArrayLike, Ts: float, f: float, zeta: float) -> np.ndarray:
    """(n, 2) free responses of the load filter H from the first finite sample of ``a`` (NaN
    before it): what an unknown state of the load at that sample adds to
    :func:`load_acceleration` (a recording that starts with the load ringing, mid-motion or
    half a kernel after an acceleration step).  Any start state adds a combination of the
    two columns; they decay as exp(-zeta 2 pi f t)."""
    a = np.asarray(a, dtype=float)
    out = np.full((a.size, 2), np.nan)
    fin = np.flatnonzero(np.isfinite(a))
    if fin.size == 0:
        return out
    k0 = int(fin[0])
    b, den = load_filter(f, zeta, Ts)
    zero = np.zeros(a.size - k0)
    for j in range(2):
        zi = np.zeros(2)
        zi[j] = 1.0
        out[k0:, j] = lfilter(b, den, zero, zi=zi)[0]
    return out
