"""The sensor model: what separates a measured run from the model's own signals.

One :class:`Sensors` says what the linear scale and the current measurement do to a run:

- the controller reads, and the run records, the position rounded to ``quantum``;
- ``current_noise`` [A rms] (normal, reproducible from ``seed``) is added to the recorded
  current; with ``noise_on_stage`` it is a real current (the amplifier's ripple), so it also
  acts on the stage as a force K_f0 * noise; without, only the measurement is noisy.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

#: The force constant that turns a current-noise sample into a force on the stage [N/A]
#: (the paper's K_f0 = ripple.c[0]).
K_F0: float = 69.88


@dataclass(frozen=True)
class Sensors:
    """Scale resolution, current noise and its seed.

    Attributes
    ----------
    quantum : linear-scale resolution [m] (100 nm; 0: exact position).
    current_noise : rms of the current noise [A] (0: none).
    seed : seed of the noise generator.
    noise_on_stage : the noise is a real current acting on the stage (True) or measurement
        noise only (False).
    """

    quantum: float = 1e-7
    current_noise: float = 0.005
    seed: int = 0
    noise_on_stage: bool = True

    def __post_init__(self) -> None:
        if not (np.isfinite(self.quantum) and self.quantum >= 0):
            raise ValueError(f"Sensors: quantum = {self.quantum!r} must be >= 0 [m]")
        if not (np.isfinite(self.current_noise) and self.current_noise >= 0):
            raise ValueError(f"Sensors: current_noise = {self.current_noise!r} must be >= 0 [A]")

    def quantise(self, x: np.ndarray) -> np.ndarray:
        """Positions as the scale reads them (rounded to ``quantum``)."""
        x = np.asarray(x, dtype=float)
        return np.round(x / self.quantum) * self.quantum if self.quantum > 0 else x

    def current_noise_series(self, n: int) -> np.ndarray:
        """The n current-noise samples [A] (reproducible from ``seed``)."""
        if self.current_noise <= 0:
            return np.zeros(n)
        return np.random.default_rng(self.seed).normal(0.0, self.current_noise, n)

    def force_disturbance(self, n: int) -> np.ndarray:
        """F_ext [N] that makes the noise act on the stage (m a = K_f i - ... - F_ext); zeros
        when the noise is measurement noise only."""
        if not self.noise_on_stage:
            return np.zeros(n)
        return -K_F0 * self.current_noise_series(n)

    def to_json(self) -> dict[str, Any]:
        """The sidecar's ``sensors`` object."""
        return asdict(self)

    @classmethod
    def from_json(cls, obj: Mapping[str, Any], where: str = "sensors") -> Sensors:
        """From a sidecar ``sensors`` object; ValueError naming ``where`` and the key."""
        if not isinstance(obj, Mapping):
            raise ValueError(f"{where}: must be an object, got {type(obj).__name__}")
        unknown = set(obj) - {"quantum", "current_noise", "seed", "noise_on_stage"}
        if unknown:
            raise ValueError(f"{where}: unknown key(s) {sorted(unknown)}")
        try:
            return cls(
                quantum=float(obj.get("quantum", cls.quantum)),
                current_noise=float(obj.get("current_noise", cls.current_noise)),
                seed=int(obj.get("seed", cls.seed)),
                noise_on_stage=bool(obj.get("noise_on_stage", cls.noise_on_stage)),
            )
        except (TypeError, ValueError) as e:
            raise ValueError(f"{where}: {e}") from None


#: No sensor effects: exact position, no current noise.
IDEAL = Sensors(quantum=0.0, current_noise=0.0)
