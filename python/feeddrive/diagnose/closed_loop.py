"""Closed-loop runs of a model: a force-equivalent PID, reference profiles, and a run writer.

The diagnosis needs closed-loop simulations twice: to make test data with hidden effects
(the FMU with one effect on, controlled like a real machine) and to re-simulate a model
against a measured run whose controller the sidecar JSON describes (the closed-loop
position-error gap).  The controller is described in the sidecar as::

    "controller": {"type": "pid", "Kp": 6e5, "Kv": 6.7e3, "Ki": 2e7, "force_per_volt": 78.7}

(force-equivalent gains in N/m, N s/m, N/(m s); u = F / force_per_volt), and the reference
as the run's ``x_ref`` column.  The validation package's ``state_space`` specs are accepted
too (:func:`controller_from_meta`); other types are not re-simulated (the gap is then the
force residual alone, and the diagnosis says so).
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..data import Run
from ..fmu import Plant
from ..model_file import ModelFile
from ..simulate import simulate_closed_loop

#: The force-equivalent gains MODEL.md quotes as one workable design.
#: MODEL.md's state-feedback gains (Kp 6e5 N/m, Kv 6.7e3 N s/m) assume an observer; a plain PID
#: with a backward-difference derivative and the current loop's 1.5-sample lag oscillates
#: with them, so the PID uses a ~20 Hz crossover (Kv/m = 186 rad/s).
DEFAULT_PID = {"type": "pid", "Kp": 2.0e5, "Kv": 3.0e3, "Ki": 3.0e6, "force_per_volt": 78.7}


@dataclass
class PIDController:
    """u[k] = (Kp e + Ki sum(e) Ts + Kv (e[k] - e[k-1]) / Ts) / force_per_volt, e = x_ref - x.

    ``x_ref`` is sampled at the controller's instants (k = 0..n).
    """

    x_ref: np.ndarray
    Ts: float = 5e-4
    Kp: float = 2.0e5
    Kv: float = 3.0e3
    Ki: float = 3.0e6
    force_per_volt: float = 78.7
    u_limit: float = 10.0

    def reset(self) -> None:
        """Zero the integrator and the derivative memory."""
        self._q = 0.0
        self._e_prev: float | None = None

    def step(self, x_meas: float, k: int) -> float:
        """Controller output [V] at sample k from the measured position [m]."""
        e = float(self.x_ref[min(k, len(self.x_ref) - 1)]) - x_meas
        de = 0.0 if self._e_prev is None else (e - self._e_prev) / self.Ts
        self._e_prev = e
        self._q += e * self.Ts
        F = self.Kp * e + self.Ki * self._q + self.Kv * de
        return float(np.clip(F / self.force_per_volt, -self.u_limit, self.u_limit))

    @classmethod
    def from_meta(cls, spec: Mapping, x_ref: np.ndarray, Ts: float) -> "PIDController":
        """From a sidecar ``controller`` object (see module docstring)."""
        if spec.get("type") != "pid":
            raise ValueError(f"controller type {spec.get('type')!r} is not 'pid'")
        try:
            return cls(x_ref=np.asarray(x_ref, dtype=float), Ts=Ts, Kp=float(spec["Kp"]),
                       Kv=float(spec["Kv"]), Ki=float(spec["Ki"]),
                       force_per_volt=float(spec["force_per_volt"]),
                       u_limit=float(spec.get("u_limit", 10.0)))
        except KeyError as e:
            raise ValueError(f"controller: key {e.args[0]!r} missing") from None

    def to_meta(self) -> dict:
        """The sidecar description of this controller."""
        return {"type": "pid", "Kp": self.Kp, "Kv": self.Kv, "Ki": self.Ki,
                "force_per_volt": self.force_per_volt, "u_limit": self.u_limit}


def controller_from_meta(spec: Mapping, x_ref: np.ndarray, Ts: float):
    """The controller a run's sidecar ``controller`` object describes: ``pid`` (this module)
    or any type ``feeddrive.validation.controllers.make_controller`` knows (``state_space``).
    ValueError when the type is unknown or the spec incomplete."""
    if not isinstance(spec, Mapping):
        raise ValueError(f"controller spec must be an object, got {type(spec).__name__}")
    if spec.get("type") == "pid":
        return PIDController.from_meta(spec, x_ref, Ts)
    from ..validation.controllers import make_controller
    return make_controller(spec, np.asarray(x_ref, dtype=float))


def sinusoid_reference(duration: float, Ts: float = 5e-4, amplitude: float = 0.03,
                       period: float = 6.0, centre: float = 0.15) -> np.ndarray:
    """x_ref = centre - amplitude cos(2 pi t / period): starts at rest at the lower end."""
    t = np.arange(int(round(duration / Ts)) + 1) * Ts
    return centre - amplitude * np.cos(2 * np.pi * t / period)


def constant_speed_reference(speeds: list[float], stroke: float = 0.04, x0: float = 0.13,
                             Ts: float = 5e-4, accel: float = 2.0, dwell: float = 0.1
                             ) -> np.ndarray:
    """Back-and-forth moves over ``stroke`` [m] at each speed [m/s], trapezoidal velocity.

    Each speed gives one forward and one backward move with acceleration ``accel`` and a
    ``dwell`` [s] at rest between moves.
    """
    pieces = [np.full(int(dwell / Ts), x0)]
    x = x0
    for s in speeds:
        for sign in (1.0, -1.0):
            ta = s / accel
            da = 0.5 * accel * ta**2
            if 2 * da > stroke:
                raise ValueError(f"speed {s} m/s cannot be reached within {stroke} m")
            tc = (stroke - 2 * da) / s
            T = 2 * ta + tc
            t = np.arange(int(np.ceil(T / Ts)) + 1) * Ts
            t = np.minimum(t, T)
            d = np.where(t < ta, 0.5 * accel * t**2,
                         np.where(t < ta + tc, da + s * (t - ta),
                                  stroke - 0.5 * accel * np.maximum(T - t, 0) ** 2))
            pieces.append(x + sign * d[1:])
            x = x + sign * stroke
            pieces.append(np.full(int(dwell / Ts), x))
    return np.concatenate(pieces)


def simulate_run(model: ModelFile, x_ref: np.ndarray, controller=None,
                 Ts: float = 5e-4, quantum: float = 1e-7, current_noise: float = 0.0,
                 seed: int = 0, F_load: float = 0.0, name: str = "sim",
                 plant: Plant | None = None) -> Run:
    """Run ``model`` in the FMU in closed loop on ``x_ref`` and return a DATA.md run.

    ``controller``: anything with ``reset()`` and ``step(x_meas, k)`` (default: the PID on
    ``x_ref``).  Columns: time, u, i (the FMU's current held over [t_k, t_k+1), plus noise of
    rms ``current_noise`` [A]), x (quantised to ``quantum``), x_ref, F_load.  The sidecar
    meta records the controller, the sample time and the seed.
    """
    ctl = controller or PIDController(x_ref=np.asarray(x_ref, dtype=float), Ts=Ts)
    n = len(x_ref) - 1
    own = plant is None
    p = plant or Plant(model.fmu_parameters())
    try:
        res = simulate_closed_loop(p, ctl, n=n, x0=float(x_ref[0]), Ts=Ts, quantum=quantum,
                                   F_ext=F_load)
    finally:
        if own:
            p.close()
    rng = np.random.default_rng(seed)
    # feeddrive.simulate records i[k] as Eq. 2's i[k], the current held over [t_k, t_k+1)
    i_held = np.asarray(res["i"], dtype=float)
    i_meas = i_held + current_noise * rng.standard_normal(len(i_held))
    spec = ctl.to_meta() if hasattr(ctl, "to_meta") else {"type": type(ctl).__name__}
    meta = {"kind": "closed_loop", "Ts": Ts, "controller": spec, "seed": seed,
            "quantum": quantum, "current_noise_rms": current_noise, "name": name}
    return Run(time=np.asarray(res["time"]), u=np.asarray(res["u"]), x=np.asarray(res["x_meas"]),
               i=i_meas, x_ref=np.asarray(x_ref, dtype=float),
               F_load=np.full(n + 1, float(F_load)), meta=meta)
