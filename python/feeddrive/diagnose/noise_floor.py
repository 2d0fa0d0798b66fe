"""The noise floor: the force residual that the sensors alone explain, per sample.

The floor measures the sensors, never the excitation: a PRBS, an impact or a ringing
mode is force the model has to explain, not noise.  Three sources, each carried through the
estimator that turns it into force (the residual is ``r = K*F - m a``, ``a`` the
Savitzky-Golay second derivative ``c`` of the position):

- **position quantisation** with step q (the sidecar's ``sensors.quantum``, else the
  smallest step between the distinct positions of the run) reaches the residual through
  the acceleration estimate and through the friction the model computes from the measured
  motion: a stuck GMS element turns a position error into k_i times it (1.8e6 N/m and
  100 nm: 0.05 N), the velocity the friction sees moves the Stribeck level and the instant
  an element sticks.  No closed form holds all of that, so the residual is re-computed on
  the same motion read by a scale whose grid is shifted by a random fraction of a step
  (the smoothed measured position re-rounded: the rounding error keeps its structure, a
  slow sawtooth at low speed, a constant at rest; ``POSITION_DRAWS`` draws from a fixed
  seed), with everything else as measured; half the per-sample variance of the change
  (two readings, two rounding errors), averaged over ``SMOOTH_WINDOWS`` windows, is the
  floor's part from quantisation;
- **current-measurement noise** s_i [A], times K_f: the sidecar's ``sensors.current_noise``
  when it states one; else measured as what the command does not explain, ``i - G(z) u``
  (the model's current loop: a PRBS or any other command cancels), its high-frequency part
  ``e - S e`` (S the Savitzky-Golay smoother of the same window and order; white noise of
  variance s^2 leaves ``s^2 (1 - S_00)``), robust std (median absolute deviation) per block
  of ``BLOCK_WINDOWS`` windows, the median over the blocks where the command is quietest
  (the lowest ``QUIET_SHARE`` of the command's own high-frequency activity: where the
  current loop model is least exercised).  Mechanical high-frequency content (impacts,
  ringing, fast reversals) does not enter the current, so it does not enter the floor.  A
  sidecar with ``sensors.noise_on_stage: true`` says the noise is a real current: the
  recorded current then carries the force the stage felt, and the residual sees none of
  it (the floor keeps s_i for the record, and no force from it).  Without a current column
  the motor force is the command (``gain u`` or ``K_f G u``): the sidecar's current noise,
  if stated, is an unmeasured force on the stage and counts whole; else the command's own
  high-frequency part over its quietest blocks (a controller's output driven by noise);
  through the midpoint of the held samples and K: ``s ||K * [1/2, 1/2]||``;
- **timing jitter**: the scatter of the sampling intervals around their median is
  ``sqrt(2) s_t`` for time stamps off by s_t; a position read s_t late is off by ``v s_t``,
  so ``m |v| s_t ||c||``.

They are independent, so their variances add.  The floor is what a perfect model would
still leave; a residual at a few times the floor is what real data look like (other
integrators and filters, slightly different friction); see :mod:`scoring` for the factors.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.signal import savgol_coeffs, savgol_filter

from ..data import Run
from ..harness.sidecar import read_sidecar
from ..physics import (
    DEFAULT_V_STICK,
    PlantParameters,
    friction_velocity,
    gms_force,
    karnopp_friction,
    load_acceleration,
    measured_motion,
)
from ..physics import force_residual as eq1_residual
from ..residual import DEFAULT_POLYORDER, RunResidual, run_force_gain
from ..signals import odd_window
from .localise import regime_masks

#: Consistency constant of the median absolute deviation for a normal distribution.
MAD_NORMAL = 1.4826
#: Block length of the current-noise estimate, in Savitzky-Golay windows.
BLOCK_WINDOWS = 10
#: Share of the blocks, quietest command first, the current-noise estimate uses.
QUIET_SHARE = 0.25
#: Draws of the shifted scale grid, their seed, and the averaging of the squared change
#: [Savitzky-Golay windows].
POSITION_DRAWS = 2
#: Savitzky-Golay window [samples] of the position the shifted grid re-reads (short: a
#: longer one bends the ramps of a move by more than a step).
SMOOTH_POSITION = 7
POSITION_SEED = 20140
SMOOTH_WINDOWS = 5


@dataclass
class NoiseFloor:
    """Noise floor of one run: the sources' sizes and the per-sample floor [N]."""

    quantum_m: float  #: position step used [m]
    quantum_source: str  #: "sidecar" or "data"
    force_noise_N: float  #: std of the unfiltered motor-force noise [N]
    jitter_s: float  #: std of the sampling interval [s]
    quantisation_N: float  #: force std of the acceleration estimate's rounding while moving [N]
    force_N: float  #: force std from the force-measurement noise [N]
    moving: np.ndarray  #: samples where the quantisation error is white
    jitter_force: np.ndarray  #: per-sample force std from timing jitter [N]
    #: per-sample force std from the position's rounding through the whole residual [N]
    position_force: np.ndarray = field(default_factory=lambda: np.zeros(0))
    current_noise_A: float | None = None  #: s_i used [A] (None: no current column)
    noise_source: str = ""  #: where the force noise came from

    @property
    def sigma(self) -> np.ndarray:
        """Per-sample floor [N] (all sources)."""
        if self.position_force.size:
            pos2 = self.position_force**2
        else:
            pos2 = self.quantisation_N**2 * self.moving
        return np.sqrt(pos2 + self.force_N**2 + self.jitter_force**2)

    def rms(self, mask: np.ndarray | None = None) -> float:
        """rms of the floor over ``mask`` (all samples when None) [N]."""
        s = self.sigma if mask is None else self.sigma[mask]
        return float(np.sqrt(np.mean(s**2))) if s.size else 0.0

    def to_json(self, valid: np.ndarray) -> dict:
        """diagnosis.json ``noise_floor.runs`` entry over the ``valid`` samples."""
        pos = (
            self.position_force[valid]
            if self.position_force.size
            else self.quantisation_N * self.moving[valid]
        )
        return {
            "quantum_m": self.quantum_m,
            "quantum_source": self.quantum_source,
            "force_noise_N": self.force_noise_N,
            "current_noise_A": self.current_noise_A,
            "force_noise_source": self.noise_source,
            "jitter_s": self.jitter_s,
            "from_quantisation_N": float(np.sqrt(np.mean(pos**2))) if pos.size else 0.0,
            "from_acceleration_quantisation_N": self.quantisation_N
            * float(np.sqrt(np.mean(self.moving[valid]))),
            "from_force_noise_N": self.force_N,
            "from_jitter_N": float(np.sqrt(np.mean(self.jitter_force[valid] ** 2))),
            "rms_N": self.rms(valid),
        }


def position_quantum(x: np.ndarray) -> float:
    """The encoder step of a position record [m]: the smallest step between distinct
    positions (rounded to 1e-12 m), 0 when the position never changes."""
    u = np.unique(np.round(np.asarray(x, dtype=float), 12))
    if u.size < 2:
        return 0.0
    d = np.diff(u)
    d = d[d > 1e-12]
    return float(d.min()) if d.size else 0.0


def _sensors(run: Run) -> dict:
    """The sidecar's ``sensors`` object as given (empty when it has none)."""
    meta = run.meta or {}
    return meta["sensors"] if isinstance(meta.get("sensors"), dict) else {}


def run_quantum(run: Run) -> tuple[float, str]:
    """The position step of a run: the sidecar's ``sensors.quantum`` when the sidecar gives
    one, else :func:`position_quantum` of the data."""
    if "quantum" in _sensors(run):
        q = read_sidecar(run.meta, where=f"{run.path or run.name}: sidecar").sensors.quantum
        return float(q), "sidecar"
    return position_quantum(run.x), "data"


def stated_current_noise(run: Run) -> tuple[float | None, bool]:
    """The sidecar's ``sensors.current_noise`` [A] (None when it states none) and whether
    it states the noise acts on the stage (``noise_on_stage: true``)."""
    sens = _sensors(run)
    if "current_noise" not in sens:
        return None, False
    side = read_sidecar(run.meta, where=f"{run.path or run.name}: sidecar").sensors
    return float(side.current_noise), bool(sens.get("noise_on_stage", False))


def _hf(y: np.ndarray, window: int, polyorder: int) -> tuple[np.ndarray, float]:
    """High-frequency part ``y - S y`` and S's centre weight S_00."""
    hf = y - savgol_filter(y, window, polyorder)
    return hf, float(savgol_coeffs(window, polyorder)[window // 2])


def _mad_std(y: np.ndarray) -> float:
    return MAD_NORMAL * float(np.median(np.abs(y - np.median(y)))) if y.size else 0.0


def force_noise(
    F: np.ndarray,
    window: int,
    polyorder: int = DEFAULT_POLYORDER,
    command: np.ndarray | None = None,
) -> float:
    """Robust std of the white part of a signal (see module docstring).

    Parameters
    ----------
    F : the signal whose noise is wanted (e.g. ``i - G(z) u``, or a force).
    window, polyorder : the Savitzky-Golay smoother that splits off the high frequencies.
    command : the command the signal follows (same length); when given the estimate uses
        the blocks where the command's high-frequency part is smallest (``QUIET_SHARE``).
    """
    F = np.asarray(F, dtype=float)
    w = min(window, len(F) - (1 - len(F) % 2))
    if w < polyorder + 2:
        return 0.0
    hf, h0 = _hf(F, w, polyorder)
    scale = 1.0 / np.sqrt(1.0 - h0)
    L = BLOCK_WINDOWS * w
    nb = len(F) // L
    if command is None or nb < 2:
        return _mad_std(hf) * scale
    hc, _ = _hf(np.asarray(command, dtype=float), w, polyorder)
    act = np.array([np.sqrt(np.mean(hc[b * L : (b + 1) * L] ** 2)) for b in range(nb)])
    keep = np.argsort(act, kind="stable")[: max(1, int(np.ceil(QUIET_SHARE * nb)))]
    return float(np.median([_mad_std(hf[b * L : (b + 1) * L]) for b in keep])) * scale


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


def motor_force_noise(
    run: Run,
    P: PlantParameters,
    window: int,
    polyorder: int = DEFAULT_POLYORDER,
    force_gain: float | None = None,
) -> tuple[float, float | None, str]:
    """(std of the motor-force noise the residual sees [N], s_i [A] or None, source)."""
    kf = float(np.median(P.K_f(np.asarray(run.x, dtype=float))))
    stated, on_stage = stated_current_noise(run)
    u = np.asarray(run.u, dtype=float)
    if run.i is not None:
        if stated is not None:
            if on_stage:
                return (
                    0.0,
                    stated,
                    (
                        "sidecar sensors.current_noise, noise_on_stage: the "
                        "recorded current is the current that acted"
                    ),
                )
            return kf * stated, stated, "sidecar sensors.current_noise"
        e = np.asarray(run.i, dtype=float) - P.current.current(u)
        s_i = force_noise(e, window, polyorder, command=u)
        return kf * s_i, s_i, "data: i - G(z) u where the command is quietest"
    if stated is not None:
        return kf * stated, stated, "sidecar sensors.current_noise (unmeasured force)"
    F = raw_force(run, P, force_gain)
    return (
        force_noise(F, window, polyorder, command=F),
        None,
        "data: the command's high-frequency part where it is quietest",
    )


def position_noise_force(
    q: RunResidual,
    P: PlantParameters,
    quantum: float,
    polyorder: int = DEFAULT_POLYORDER,
    draws: int = POSITION_DRAWS,
) -> np.ndarray:
    """Per-sample std [N] of the residual from the position's rounding: the motion read by a
    scale whose grid is shifted by a random fraction of ``quantum`` (the smoothed measured
    position re-rounded), the acceleration and the model's friction re-computed, the motor
    force and the start state kept; two readings differ by two rounding errors, so half the
    variance of the change (module docstring)."""
    n = len(q.x)
    if quantum <= 0 or n < 3:
        return np.zeros(n)
    rng = np.random.default_rng(POSITION_SEED)
    w = len(q.K) + 2
    ws = odd_window(SMOOTH_POSITION, n)
    smooth = savgol_filter(q.x, ws, min(polyorder, ws - 1))
    load = 0.0
    var = np.zeros(n)
    for _ in range(draws):
        shift = quantum * float(rng.random())
        x = np.round((smooth + shift) / quantum) * quantum - shift
        v, a, K = measured_motion(x, q.Ts, w, polyorder)
        if P.prerolling:
            F0 = q.start.F0 if q.start is not None else None
            F_f = gms_force(x, friction_velocity(x, q.Ts, w, polyorder), q.Ts, P.friction, F0=F0)
        else:
            F_f, _ = karnopp_friction(v, q.F_app, P.friction, DEFAULT_V_STICK, x)
        c = P.compliance
        if c.on:
            load = c.m2 * (
                load_acceleration(a, q.Ts, c.f, c.zeta) - load_acceleration(q.a, q.Ts, c.f, c.zeta)
            )
        d = eq1_residual(q.F_app, F_f, a, P.m, K) - load - q.r
        var += np.nan_to_num(d) ** 2 / (2.0 * draws)
    L = max(1, min(SMOOTH_WINDOWS * w, n))
    sigma = np.sqrt(np.convolve(var, np.ones(L) / L, mode="same"))
    # a GMS element's force is k_i-Lipschitz in the position it is driven by: a rounding
    # error (at most q / 2) moves the friction by at most sum k_i q / 2, the acceleration by
    # m q / 2 ||c||; a larger change is the re-reading's own chance (which element sticks
    # first at a reversal), not what one rounding does
    k = float(np.sum(P.friction.k)) if P.prerolling else 0.0
    coef = savgol_coeffs(w, min(max(polyorder, 2), w - 1), deriv=2, delta=q.Ts)
    cap = quantum / 2.0 * np.hypot(k, P.m * float(np.linalg.norm(coef)))
    return np.minimum(sigma, cap)


def noise_floor(
    run: Run,
    q: RunResidual,
    P: PlantParameters,
    force_gain: float | None = None,
    polyorder: int = DEFAULT_POLYORDER,
) -> NoiseFloor:
    """The noise floor of ``run`` whose residual with the model ``P`` is ``q``."""
    m = P.m
    w = len(q.K) + 2
    c = savgol_coeffs(w, min(max(polyorder, 2), w - 1), deriv=2, delta=q.Ts)
    c_norm = float(np.linalg.norm(c))
    K_norm = float(np.linalg.norm(np.convolve(q.K, [0.5, 0.5])))
    quantum, src = run_quantum(run)
    s_f, s_i, nsrc = motor_force_noise(run, P, w, polyorder, force_gain)
    dt = np.diff(q.time)
    jitter = (
        MAD_NORMAL * float(np.median(np.abs(dt - np.median(dt)))) / np.sqrt(2.0) if dt.size else 0.0
    )
    # moving by more than a step over the window: the rounding error changes there
    moving = np.abs(q.v) * w * q.Ts > quantum
    s_q = m * quantum / np.sqrt(12.0) * c_norm
    s_pos = position_noise_force(q, P, quantum, polyorder)
    return NoiseFloor(
        quantum_m=quantum,
        quantum_source=src,
        force_noise_N=s_f,
        jitter_s=jitter,
        quantisation_N=float(s_q),
        force_N=float(s_f * K_norm),
        moving=moving,
        jitter_force=m * np.abs(q.v) * jitter * c_norm,
        position_force=s_pos,
        current_noise_A=s_i,
        noise_source=nsrc,
    )


def floor_table(res: list[RunResidual], floors: list[NoiseFloor]) -> dict:
    """diagnosis.json ``noise_floor``: per run (sources and rms), per regime and overall rms [N]."""
    masks = [regime_masks(q) for q in res]
    s = np.concatenate([f.sigma[q.valid] for f, q in zip(floors, res, strict=True)])
    names = list(dict.fromkeys(k for mk in masks for k in mk))
    regimes = {}
    for name in names:
        sel = np.concatenate(
            [
                mk.get(name, np.zeros(len(q.r), bool))[q.valid]
                for mk, q in zip(masks, res, strict=True)
            ]
        )
        if sel.any():
            regimes[name] = float(np.sqrt(np.mean(s[sel] ** 2)))
    return {
        "rms_N": float(np.sqrt(np.mean(s**2))),
        "runs": {q.name: f.to_json(q.valid) for f, q in zip(floors, res, strict=True)},
        "regimes_rms_N": regimes,
    }
