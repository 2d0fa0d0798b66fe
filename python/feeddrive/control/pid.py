"""The position PID, force-equivalent gains, optionally with a lead filter.

    e[k] = r[k] - x_meas[k]
    q[k] = q[k-1] + Ts e[k]
    D[k] = Kv (e[k] - e[k-1]) / Ts                        (tf = 0; D[0] = 0)
         = a D[k-1] + b (e[k] - e[k-1]), a = tf/(tf+Ts), b = Kv/(tf+Ts)   (tf > 0)
    F[k] = Kp e[k] + Ki q[k] + D[k]                        [N]
    F[k] -> lead filter (optional: (1 + s/w_z)/(1 + s/w_p), Tustin, unit DC gain)
    u[k] = clip(F[k] / force_per_volt + u_ff[k], -u_limit, u_limit)    [V]

Anti-windup (optional): while u is clamped and e pushes further into the clamp, q keeps its
previous value (conditional integration).  With tf = 0, no lead and no anti-windup this is
the force-equivalent PID the diagnosis's hidden-effect tests are tuned on.

Gains: Kp [N/m], Kv [N s/m], Ki [N/(m s)]; ``force_per_volt`` [N/V] is K_f0 G(1) of the
drive (78.7 N/V for the paper's, :meth:`PID.from_force_gains` takes it from a design model).
The plain PID cannot take the state-feedback design's gains (6e5/6.7e3/2e7 assume an
observer): with the current loop's 1.5-sample lag it oscillates, so :data:`DEFAULT_GAINS`
has a ~20 Hz crossover (Kv/m = 186 rad/s).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal

from .design_model import DesignModel
from .margins import Margins, frequency_grid, loop_margins

#: Force-equivalent gains of the default PID [N/m, N s/m, N/(m s)] and its scale [N/V].
DEFAULT_GAINS: dict[str, float] = {"Kp": 2.0e5, "Kv": 3.0e3, "Ki": 3.0e6}
DEFAULT_FORCE_PER_VOLT: float = 78.7
DEFAULT_U_LIMIT: float = 10.0  #: amplifier reference range +- [V]


@dataclass(frozen=True)
class PIDSettings:
    """The PID's gains and options with their defaults (see :class:`PID`): the one list the
    controller, its spec (:func:`feeddrive.harness.controllers.pid_spec`) and the spec's
    keys share."""

    Kp: float = DEFAULT_GAINS["Kp"]  #: [N/m]
    Kv: float = DEFAULT_GAINS["Kv"]  #: [N s/m]
    Ki: float = DEFAULT_GAINS["Ki"]  #: [N/(m s)]
    force_per_volt: float = DEFAULT_FORCE_PER_VOLT  #: [N/V]
    u_limit: float = DEFAULT_U_LIMIT  #: [V]
    tf: float = 0.0  #: derivative filter time constant [s]
    anti_windup: bool = False


def lead_coefficients(zero_hz: float, pole_hz: float, Ts: float) -> tuple[np.ndarray, np.ndarray]:
    """Tustin discretisation (b, a) of (1 + s/w_z)/(1 + s/w_p), unit gain at DC."""
    if not (0 < zero_hz < pole_hz < 0.5 / Ts):
        raise ValueError(
            f"pid.py: lead needs 0 < zero_hz < pole_hz < Nyquist "
            f"(got {zero_hz}, {pole_hz}, Nyquist {0.5 / Ts:g} Hz)"
        )
    wz, wp = 2 * np.pi * zero_hz, 2 * np.pi * pole_hz
    b, a = signal.bilinear([1.0 / wz, 1.0], [1.0 / wp, 1.0], fs=1.0 / Ts)
    return b / a[0], a / a[0]


class PID:
    """Position PID (see module docstring), ``reset()`` / ``step(x_meas, k) -> u`` [V].

    Parameters
    ----------
    reference : x_ref[k] [m] sampled at Ts (held at its last value beyond the end).
    Ts : sample time [s].
    Kp, Kv, Ki : force-equivalent gains [N/m], [N s/m], [N/(m s)] (>= 0).
    force_per_volt : N per V of the amplifier + motor at DC.
    u_limit : output clamp +- [V].
    tf : derivative filter time constant [s] (0: plain backward difference).
    anti_windup : conditional integration while clamped.
    lead : (zero_hz, pole_hz) of a lead filter on the force command, or None.
    u_ff : feedforward voltage per sample (zero beyond its end), or None.

    The defaults of the settings are :class:`PIDSettings`'s.
    """

    def __init__(
        self,
        reference: ArrayLike,
        Ts: float = 5e-4,
        Kp: float = PIDSettings.Kp,
        Kv: float = PIDSettings.Kv,
        Ki: float = PIDSettings.Ki,
        force_per_volt: float = PIDSettings.force_per_volt,
        u_limit: float = PIDSettings.u_limit,
        tf: float = PIDSettings.tf,
        anti_windup: bool = PIDSettings.anti_windup,
        lead: tuple[float, float] | None = None,
        u_ff: ArrayLike | None = None,
    ) -> None:
        if not Ts > 0 or not tf >= 0:
            raise ValueError(f"pid.py: need Ts > 0 and tf >= 0 (got Ts={Ts}, tf={tf})")
        if min(Kp, Kv, Ki) < 0:
            raise ValueError(f"pid.py: gains must be >= 0 (got Kp={Kp}, Kv={Kv}, Ki={Ki})")
        if not force_per_volt > 0 or not u_limit > 0:
            raise ValueError(
                f"pid.py: need force_per_volt > 0 and u_limit > 0 (got {force_per_volt}, {u_limit})"
            )
        self.x_ref = np.asarray(reference, dtype=float).copy()
        if self.x_ref.ndim != 1 or self.x_ref.size == 0:
            raise ValueError("pid.py: reference must be a non-empty 1-D array")
        self.Ts, self.Kp, self.Kv, self.Ki = float(Ts), float(Kp), float(Kv), float(Ki)
        self.force_per_volt, self.u_limit = float(force_per_volt), float(u_limit)
        self.tf, self.anti_windup = float(tf), bool(anti_windup)
        self._a = self.tf / (self.tf + self.Ts)
        self._b = self.Kv / (self.tf + self.Ts)
        self.lead = None if lead is None else (float(lead[0]), float(lead[1]))
        self._lead_ba = None if self.lead is None else lead_coefficients(*self.lead, self.Ts)
        self.u_ff = None if u_ff is None else np.asarray(u_ff, dtype=float).copy()
        self._uff = [] if self.u_ff is None else self.u_ff.tolist()
        self.reset()

    @classmethod
    def from_force_gains(cls, model: DesignModel, reference: ArrayLike, **kw: Any) -> PID:
        """A PID at ``model``'s Ts whose force_per_volt is the model's K_f0 G(1)."""
        return cls(reference, Ts=model.Ts, force_per_volt=1.0 / model.volts_per_newton, **kw)

    def reset(self) -> None:
        """Zero the integrator, the derivative memory and the lead filter."""
        self._q = 0.0
        self._D = 0.0
        self._e_prev: float | None = None
        self._F_prev = 0.0
        self._L_prev = 0.0

    def step(self, x_meas: float, k: int) -> float:
        """Controller output [V] at sample k from the measured position [m]."""
        e = float(self.x_ref[min(k, len(self.x_ref) - 1)]) - x_meas
        if self.tf == 0.0:
            de = 0.0 if self._e_prev is None else (e - self._e_prev) / self.Ts
            D = self.Kv * de
        else:
            D = self._a * self._D + (0.0 if self._e_prev is None else self._b * (e - self._e_prev))
            self._D = D
        self._e_prev = e
        q_before = self._q
        self._q += e * self.Ts
        F = self.Kp * e + self.Ki * self._q + D
        if self._lead_ba is not None:
            (b0, b1), (_, a1) = self._lead_ba
            L = b0 * F + b1 * self._F_prev - a1 * self._L_prev
            self._F_prev, self._L_prev = F, L
            F = L
        u = F / self.force_per_volt
        if self._uff:
            u += self._uff[k] if k < len(self._uff) else 0.0
        if self.anti_windup and abs(u) > self.u_limit and u * e > 0:
            self._q = q_before
        return float(np.clip(u, -self.u_limit, self.u_limit))

    def freqresp(self, f: np.ndarray) -> np.ndarray:
        """Feedback law x_meas -> u (r = 0, no clamp) at frequencies f [Hz]."""
        z = np.exp(1j * 2 * np.pi * np.asarray(f, dtype=float) * self.Ts)
        zi = 1.0 / z
        D = self._b * (1 - zi) / (1 - self._a * zi)
        C = self.Kp + self.Ki * self.Ts / (1 - zi) + D
        if self._lead_ba is not None:
            b, a = self._lead_ba
            C = C * (b[0] + b[1] * zi) / (a[0] + a[1] * zi)
        return -C / self.force_per_volt

    def margins(self, model: DesignModel) -> Margins:
        """Loop margins with ``model`` as plant."""
        f = frequency_grid(self.Ts)
        return loop_margins(f, -self.freqresp(f) * model.freqresp(f))
