"""Sensor and actuator effects of a real measurement, applied to a virtual run."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..data import Run


@dataclass
class Sensors:
    """What separates a measurement from the model's own signals.

    Attributes
    ----------
    quantum : linear-scale resolution [m] (100 nm).
    current_noise : rms noise of the motor current [A]: it is real (it acts on the stage as a
        force K_f0 * noise) and it is what the amplifier's feedback reports.
    seed : seed of the noise generator.
    """

    quantum: float = 1e-7
    current_noise: float = 0.005
    seed: int = 0
    K_f0: float = 69.88

    def current_noise_series(self, n: int) -> np.ndarray:
        """The current noise samples [A] (reproducible from the seed)."""
        if self.current_noise <= 0:
            return np.zeros(n)
        return np.random.default_rng(self.seed).normal(0.0, self.current_noise, n)

    def force_disturbance(self, n: int) -> np.ndarray:
        """F_ext [N] that makes the noise act on the stage (m a = K_f i - ... - F_ext)."""
        return -self.K_f0 * self.current_noise_series(n)


def to_run(res, sensors: Sensors, x_ref: np.ndarray | None = None, F_load: float | np.ndarray = 0.0,
           meta: dict | None = None) -> Run:
    """A DATA.md run from a simulation result: quantised x, current with its noise."""
    n = len(res["time"])
    noise = sensors.current_noise_series(n)
    x = np.round(res["x"] / sensors.quantum) * sensors.quantum if sensors.quantum > 0 else res["x"]
    return Run(time=np.asarray(res["time"], float), u=np.asarray(res["u"], float), x=x,
               i=np.asarray(res["i"], float) + noise,
               x_ref=None if x_ref is None else np.asarray(x_ref, float),
               F_load=np.broadcast_to(np.asarray(F_load, float), (n,)).copy(),
               meta=dict(meta or {}))
