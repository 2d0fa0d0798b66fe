"""The noise floor: the force residual that measurement alone explains, per sample.

Three sources, each carried through the estimator that turns it into force (the residual
is ``r = K*F - m a``, ``a`` the Savitzky-Golay second derivative ``c`` of the position):

- **position quantisation** with step q (the sidecar's ``sensors.quantum``, else the
  smallest step between the distinct positions of the run): a rounding error uniform over
  one step, white while the stage moves by more than a step per window, so
  ``sigma_a = q / sqrt(12) * ||c||`` and the force ``m sigma_a``; a stage that stands still
  reads a constant position and gets none;
- **force-measurement noise** (current noise times K_f, or noise on u times the gain): the
  high-frequency part of the raw force column (``K_f(x) i``, ``gain u`` or
  ``K_f(x) G(1) u``, as :func:`residual.motor_force` uses it, before the midpoint of the
  held samples), ``F - S F`` with S the Savitzky-Golay smoother of the same window and order
  (a projection: white noise of variance s^2 leaves ``s^2 (1 - S_00)`` there), taken
  robustly (median absolute deviation, so that the steps of a controller count little),
  then through the midpoint and K: ``s ||K * [1/2, 1/2]||``.  A controller's own
  high-frequency output counts as noise here: the floor errs on the high side;
- **timing jitter**: the scatter of the sampling intervals around their median is
  ``sqrt(2) s_t`` for time stamps off by s_t; a position read s_t late is off by ``v s_t``,
  so ``m |v| s_t ||c||``.

They are independent, so their variances add.  The floor is what a perfect model would
still leave; a residual at a few times the floor is what real data look like (other
integrators and filters, slightly different friction); see :mod:`scoring` for the factors.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import savgol_coeffs, savgol_filter

from ..data import Run
from ..harness.sidecar import read_sidecar
from ..physics import PlantParameters
from .localise import regime_masks
from .residual import DEFAULT_POLYORDER, RunResidual, run_force_gain

#: Consistency constant of the median absolute deviation for a normal distribution.
MAD_NORMAL = 1.4826


@dataclass
class NoiseFloor:
    """Noise floor of one run: the sources' sizes and the per-sample floor [N]."""

    quantum_m: float              #: position step used [m]
    quantum_source: str           #: "sidecar" or "data"
    force_noise_N: float          #: std of the unfiltered motor-force noise [N]
    jitter_s: float               #: std of the sampling interval [s]
    quantisation_N: float         #: force std from quantisation while moving [N]
    force_N: float                #: force std from the force-measurement noise [N]
    moving: np.ndarray            #: samples where the quantisation error is white
    jitter_force: np.ndarray      #: per-sample force std from timing jitter [N]

    @property
    def sigma(self) -> np.ndarray:
        """Per-sample floor [N] (all sources)."""
        return np.sqrt(self.quantisation_N**2 * self.moving + self.force_N**2
                       + self.jitter_force**2)

    def rms(self, mask: np.ndarray | None = None) -> float:
        """rms of the floor over ``mask`` (all samples when None) [N]."""
        s = self.sigma if mask is None else self.sigma[mask]
        return float(np.sqrt(np.mean(s**2))) if s.size else 0.0

    def to_json(self, valid: np.ndarray) -> dict:
        """diagnosis.json ``noise_floor.runs`` entry over the ``valid`` samples."""
        return {"quantum_m": self.quantum_m, "quantum_source": self.quantum_source,
                "force_noise_N": self.force_noise_N, "jitter_s": self.jitter_s,
                "from_quantisation_N": self.quantisation_N * float(np.sqrt(np.mean(self.moving[valid]))),
                "from_force_noise_N": self.force_N,
                "from_jitter_N": float(np.sqrt(np.mean(self.jitter_force[valid] ** 2))),
                "rms_N": self.rms(valid)}


def position_quantum(x: np.ndarray) -> float:
    """The encoder step of a position record [m]: the smallest step between distinct
    positions (rounded to 1e-12 m), 0 when the position never changes."""
    u = np.unique(np.round(np.asarray(x, dtype=float), 12))
    if u.size < 2:
        return 0.0
    d = np.diff(u)
    d = d[d > 1e-12]
    return float(d.min()) if d.size else 0.0


def run_quantum(run: Run) -> tuple[float, str]:
    """The position step of a run: the sidecar's ``sensors.quantum`` when the sidecar gives
    one, else :func:`position_quantum` of the data."""
    meta = run.meta or {}
    if isinstance(meta.get("sensors"), dict) and "quantum" in meta["sensors"]:
        q = read_sidecar(meta, where=f"{run.path or run.name}: sidecar").sensors.quantum
        return float(q), "sidecar"
    return position_quantum(run.x), "data"


def force_noise(F: np.ndarray, window: int, polyorder: int = DEFAULT_POLYORDER) -> float:
    """Robust std of the white part of a force signal [N] (see module docstring)."""
    F = np.asarray(F, dtype=float)
    w = min(window, len(F) - (1 - len(F) % 2))
    if w < polyorder + 2:
        return 0.0
    hf = F - savgol_filter(F, w, polyorder)
    h0 = float(savgol_coeffs(w, polyorder)[w // 2])
    mad = float(np.median(np.abs(hf - np.median(hf))))
    return MAD_NORMAL * mad / np.sqrt(1.0 - h0)


def raw_force(run: Run, P: PlantParameters, force_gain: float | None = None) -> np.ndarray:
    """The motor force column as sampled, before the midpoint of held samples [N]
    (the same source as :func:`residual.motor_force`)."""
    x = np.asarray(run.x, dtype=float)
    if run.i is not None:
        return P.K_f(x) * np.asarray(run.i, dtype=float)
    gain = run_force_gain(run, force_gain)
    u = np.asarray(run.u, dtype=float)
    if gain is not None:
        return gain * u
    return P.K_f(x) * P.current.current(u)


def noise_floor(run: Run, q: RunResidual, P: PlantParameters, force_gain: float | None = None,
                polyorder: int = DEFAULT_POLYORDER) -> NoiseFloor:
    """The noise floor of ``run`` whose residual with the model ``P`` is ``q``."""
    m = P.m
    w = len(q.K) + 2
    c = savgol_coeffs(w, min(max(polyorder, 2), w - 1), deriv=2, delta=q.Ts)
    c_norm = float(np.linalg.norm(c))
    K_norm = float(np.linalg.norm(np.convolve(q.K, [0.5, 0.5])))
    quantum, src = run_quantum(run)
    s_f = force_noise(raw_force(run, P, force_gain), w, polyorder)
    dt = np.diff(q.time)
    jitter = MAD_NORMAL * float(np.median(np.abs(dt - np.median(dt)))) / np.sqrt(2.0) \
        if dt.size else 0.0
    # moving by more than a step over the window: the rounding error is white there
    moving = np.abs(q.v) * w * q.Ts > quantum
    s_q = m * quantum / np.sqrt(12.0) * c_norm
    s_F = s_f * K_norm
    return NoiseFloor(quantum_m=quantum, quantum_source=src, force_noise_N=s_f, jitter_s=jitter,
                      quantisation_N=float(s_q), force_N=float(s_F), moving=moving,
                      jitter_force=m * np.abs(q.v) * jitter * c_norm)


def floor_table(res: list[RunResidual], floors: list[NoiseFloor]) -> dict:
    """diagnosis.json ``noise_floor``: per run (sources and rms), per regime and overall rms [N]."""
    masks = [regime_masks(q) for q in res]
    s = np.concatenate([f.sigma[q.valid] for f, q in zip(floors, res)])
    names = list(dict.fromkeys(k for mk in masks for k in mk))
    regimes = {}
    for name in names:
        sel = np.concatenate([mk.get(name, np.zeros(len(q.r), bool))[q.valid]
                              for mk, q in zip(masks, res)])
        if sel.any():
            regimes[name] = float(np.sqrt(np.mean(s[sel] ** 2)))
    return {"rms_N": float(np.sqrt(np.mean(s**2))),
            "runs": {q.name: f.to_json(q.valid) for f, q in zip(floors, res)},
            "regimes_rms_N": regimes}
