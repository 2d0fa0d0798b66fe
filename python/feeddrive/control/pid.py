"""Discrete position PID with filtered derivative, anti-windup and output limits.

    e[k] = r[k] - y[k]
    D[k] = a D[k-1] - b (y[k] - y[k-1]),  a = Tf/(Tf + Ts), b = Kd/(Tf + Ts)
           (backward-Euler filtered derivative, on the measurement: no kick on reference steps)
    u[k] = clip(Kp e[k] + I[k] + D[k] + u_ff[k], u_min, u_max)
    I[k+1] = clip(I[k] + Ki Ts e[k], u_min, u_max), skipped while u is clamped and e pushes
             further into the clamp (conditional integration).

Gains are in volts per SI unit (Kp V/m, Ki V/(m s), Kd V s/m); :meth:`PID.from_force_gains`
converts force-equivalent gains (N/m, ...) with 1/(K_f0 G(1)) [V/N].

Default (force-equivalent) gains Kp = 8e4 N/m, Ki = 1e6 N/(m s), Kd = 2e3 N s/m,
Tf = 0.25 ms: on the design model GM 11 dB, PM 41 deg, crossover 20 Hz.  The current loop's
lag (Eq. 2, ~3 ms) keeps a plain PID well below the state feedback's stiffness (with
MODEL.md's 6e5/6.7e3/2e7 as a PID the loop has ~11 deg of phase margin).
"""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .design_model import DesignModel
from .margins import Margins, frequency_grid, loop_margins
from .state_space import DEFAULT_U_LIMITS

DEFAULT_FORCE_GAINS = {"Kp": 8.0e4, "Ki": 1.0e6, "Kd": 2.0e3}
DEFAULT_TF = 2.5e-4


class PID:
    """Position PID controller.

    Parameters
    ----------
    kp, ki, kd : gains [V/m], [V/(m s)], [V s/m].
    Ts : sample time [s].
    reference : x_ref[k] [m] (held at its last value beyond the end).
    tf : derivative filter time constant [s] (> 0).
    u_limits : output clamp [V].
    u_ff : feedforward voltage per sample (optional).
    """

    def __init__(self, kp: float, ki: float, kd: float, Ts: float, reference: ArrayLike, *,
                 tf: float = DEFAULT_TF, u_limits: tuple[float, float] = DEFAULT_U_LIMITS,
                 u_ff: ArrayLike | None = None) -> None:
        if Ts <= 0 or tf <= 0:
            raise ValueError(f"pid.py: need Ts > 0 and tf > 0 (got Ts={Ts}, tf={tf})")
        if min(kp, ki, kd) < 0:
            raise ValueError(f"pid.py: gains must be >= 0 (got {kp}, {ki}, {kd})")
        if not u_limits[0] < u_limits[1]:
            raise ValueError(f"pid.py: need u_min < u_max (got {u_limits})")
        self.kp, self.ki, self.kd, self.Ts, self.tf = float(kp), float(ki), float(kd), Ts, tf
        self.u_min, self.u_max = float(u_limits[0]), float(u_limits[1])
        self._a = tf / (tf + Ts)
        self._b = kd / (tf + Ts)
        self.reference = np.asarray(reference, dtype=float).copy()
        if self.reference.ndim != 1 or self.reference.size == 0:
            raise ValueError("pid.py: reference must be a non-empty 1-D array")
        self._r = self.reference.tolist()
        self._uff = [] if u_ff is None else np.asarray(u_ff, dtype=float).tolist()
        self.reset()

    @classmethod
    def from_force_gains(cls, model: DesignModel, reference: ArrayLike,
                         Kp: float = DEFAULT_FORCE_GAINS["Kp"],
                         Ki: float = DEFAULT_FORCE_GAINS["Ki"],
                         Kd: float = DEFAULT_FORCE_GAINS["Kd"], **kw: Any) -> "PID":
        """PID from force-equivalent gains [N/m, N/(m s), N s/m] on ``model``'s K_f0 G(1)."""
        s = model.volts_per_newton
        return cls(Kp * s, Ki * s, Kd * s, model.Ts, reference, **kw)

    def reset(self) -> None:
        """Zero the integrator and derivative filter."""
        self._I = 0.0
        self._D = 0.0
        self._y_prev: float | None = None

    def step(self, x_meas: float, k: int) -> float:
        """Controller output u [V] at sample k."""
        r = self._r[k] if k < len(self._r) else self._r[-1]
        y_prev = x_meas if self._y_prev is None else self._y_prev
        self._D = self._a * self._D - self._b * (x_meas - y_prev)
        self._y_prev = x_meas
        e = r - x_meas
        u = self.kp * e + self._I + self._D + (self._uff[k] if k < len(self._uff) else 0.0)
        sat = 0
        if u > self.u_max:
            u, sat = self.u_max, 1
        elif u < self.u_min:
            u, sat = self.u_min, -1
        if not (sat * e > 0):           # conditional integration (anti-windup)
            I = self._I + self.ki * self.Ts * e
            self._I = min(max(I, self.u_min), self.u_max)
        return u

    def freqresp(self, f: np.ndarray) -> np.ndarray:
        """Feedback law y -> u (r = 0) at frequencies f [Hz]."""
        z = np.exp(1j * 2 * np.pi * np.asarray(f, dtype=float) * self.Ts)
        zi = 1.0 / z
        return -(self.kp + self.ki * self.Ts / (z - 1.0) + self._b * (1 - zi) / (1 - self._a * zi))

    def margins(self, model: DesignModel) -> Margins:
        """Loop margins with ``model`` as plant."""
        f = frequency_grid(self.Ts)
        return loop_margins(f, -self.freqresp(f) * model.freqresp(f))
