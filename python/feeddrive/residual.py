"""The force residual of a model along a measured run (no controller needed).

Eq. 1 evaluated on the measured trajectory::

    r = K * (F_motor - F_cg(x) - F_f - F_load - F_offset) - m a

- ``a`` is the Savitzky-Golay second derivative of the measured (quantised) position, and
  ``K`` the smoothing kernel that differentiator applies to the true acceleration
  (``signals.matched_acceleration``): the force side is filtered with the same K
  so both sides see the same averaging.  r is NaN within half a window of the run's ends.
- ``F_motor = K_f(x) i`` with the measured current (taken as held over each sample interval,
  so the acceleration at t_k sees (i[k-1] + i[k]) / 2).  Without a measured current (the recording format):
  ``F_motor = force_gain * u`` when a gain [N/V] is given (CLI ``--force-gain`` or the
  sidecar's ``force_gain``), else ``K_f(x) G(z) u`` with the model's current loop (static
  gain G(1) when ``current_dynamics`` is off).  Which one was used is recorded.
- ``F_f`` is the model's friction along the measured motion: with ``prerolling`` on, the GMS
  of ``feeddrive.physics.friction_gms`` driven by the measured position (quantised, not smoothed:
  smoothing moves x by fractions of a micrometre near reversals, which the 1.8e6 N/m
  pre-rolling stiffness turns into newtons) and the 5 ms velocity of
  :func:`feeddrive.physics.friction_velocity` (where v changes sign decides when elements
  stick), started from the element forces that best explain the run's first samples
  (:mod:`feeddrive.physics.gms_start`: a recording starts holding a load, mid-motion or
  after a reversal, never from the virgin state); with it off,
  Eq. 12 as a memoryless function of v plus Karnopp stiction: where |v| < ``v_stick`` and the
  applied force is below the break-away level the stage is taken as stuck and friction
  balances the applied force (the model then predicts a = 0 there).

- with ``compliance`` on (encoder on the slide, ``compliance.sensor_side`` 0): the load's force
  on the slide, ``-m2 H(s) a`` (``feeddrive.physics.compliance``), joins the force side; H
  commutes with K, so the filtered acceleration is its input.  The load's state where the
  filtered acceleration starts (half a kernel into the run) is not measured: the free
  response of H from there is fitted to the residual and removed (two numbers per run; it
  decays within a few 1 / (2 pi zeta f)).  A model with the encoder on the load is refused
  (ValueError naming the parameter).

Positive r means the model leaves more net force than the measured acceleration shows: a
resistive force is missing (a positive offset gives r = +offset).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .data import Run
from .model_file import ModelFile
from .physics import (
    DEFAULT_V_STICK,
    GMSStart,
    PlantParameters,
    applied_force,
    compile,
    friction_velocity,
    gms_force,
    held_current,
    karnopp_friction,
    load_acceleration,
    load_free_response,
    measured_motion,
    run_load,
    started_friction,
)
from .physics import force_residual as eq1_residual
from .signals import apply_kernel, odd_window, run_label, sample_time

#: Default Savitzky-Golay window [s] (41 samples at 0.5 ms) and polynomial order.
DEFAULT_WINDOW_S = 0.02
DEFAULT_POLYORDER = 3


@dataclass
class RunResidual:
    """The force residual of one run and the signals it was computed from (all per sample).

    ``r`` and the ``*_f`` fields are filtered with ``K``; the others are unfiltered.
    """

    name: str
    Ts: float
    K: np.ndarray  #: smoothing kernel of the acceleration estimate
    time: np.ndarray
    x: np.ndarray  #: measured position [m] (maps and friction use it as is)
    v: np.ndarray  #: velocity [m/s] (the acceleration's smoother)
    a: np.ndarray  #: acceleration [m/s^2] (NaN near the ends)
    i: np.ndarray | None  #: current used [A] (midpoint of the held samples) or None
    F_motor: np.ndarray  #: K_f(x) i or gain u [N]
    F_app: np.ndarray  #: F_motor - F_cg - F_load - offset [N]
    F_f: np.ndarray  #: model friction along the motion [N]
    stuck: np.ndarray  #: bool, static model's stuck samples
    r: np.ndarray  #: force residual [N] (NaN near the ends)
    valid: np.ndarray  #: bool, samples where r is defined
    force_source: str  #: where F_motor came from
    start: GMSStart | None = None  #: estimated GMS state at the first sample (pre-rolling on)
    #: the velocity the model's friction saw [m/s] (:func:`friction_velocity` with pre-rolling
    #: on, else ``v``)
    v_f: np.ndarray = field(default_factory=lambda: np.zeros(0))
    F_load: np.ndarray = field(default_factory=lambda: np.zeros(0))
    u: np.ndarray = field(default_factory=lambda: np.zeros(0))
    x_meas: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def filt(self, y: np.ndarray) -> np.ndarray:
        """y filtered with K (NaN where the kernel overhangs the ends)."""
        return apply_kernel(np.asarray(y, dtype=float), self.K)

    @property
    def rms(self) -> float:
        """rms of r over the valid samples [N]."""
        return float(np.sqrt(np.mean(self.r[self.valid] ** 2)))


def run_force_gain(run: Run, force_gain: float | None) -> float | None:
    """The force gain [N/V] for a run without current: the argument, else meta['force_gain']."""
    if force_gain is not None:
        return float(force_gain)
    g = (run.meta or {}).get("force_gain")
    if g is None:
        return None
    try:
        return float(g)
    except (TypeError, ValueError):
        raise ValueError(f"{run_label(run)}: meta['force_gain'] = {g!r} is not a number") from None


def motor_force(
    run: Run, P: PlantParameters, x: np.ndarray, force_gain: float | None
) -> tuple[np.ndarray, np.ndarray | None, str]:
    """F_motor at the samples (midpoint of held values), the current used, and its source."""
    kf = P.K_f(x)
    if run.i is not None:
        i = held_current(run.i)
        return kf * i, i, "measured current i, F = K_f(x) i"
    gain = run_force_gain(run, force_gain)
    if gain is not None:
        return gain * held_current(run.u), None, f"no current measured: F = {gain:g} N/V * u"
    i = held_current(P.current.current(run.u))
    how = (
        "G(z) u (model's current loop)"
        if P.current.dynamics
        else "G(1) u (model's static current-loop gain)"
    )
    return kf * i, i, f"no current measured: i = {how}, F = K_f(x) i"


def model_friction(
    P: PlantParameters,
    x: np.ndarray,
    v: np.ndarray,
    F_app: np.ndarray,
    Ts: float,
    v_stick: float = DEFAULT_V_STICK,
) -> tuple[np.ndarray, np.ndarray]:
    """The model's friction along a motion (the GMS from the virgin start) and the static
    model's stuck mask."""
    if P.prerolling:
        return gms_force(x, v, Ts, P.friction), np.zeros(len(x), dtype=bool)
    return karnopp_friction(v, F_app, P.friction, v_stick, x)


def load_start_response(
    r: np.ndarray, a: np.ndarray, Ts: float, f: float, zeta: float
) -> np.ndarray:
    """The part of a residual ``r`` that the load's unknown state at the first sample with an
    acceleration explains: the least-squares combination of the two free responses of the
    load filter (:func:`feeddrive.physics.load_free_response`) started there [N]."""
    Z = load_free_response(a, Ts, f, zeta)
    ok = np.isfinite(r) & np.isfinite(Z).all(axis=1)
    out = np.zeros(len(r))
    if ok.sum() > 2:
        th = np.linalg.lstsq(Z[ok], r[ok], rcond=None)[0]
        out[ok] = Z[ok] @ th
    return out


def force_residual(
    run: Run,
    model: ModelFile,
    window: int | None = None,
    polyorder: int = DEFAULT_POLYORDER,
    force_gain: float | None = None,
    v_stick: float = DEFAULT_V_STICK,
) -> RunResidual:
    """The force residual of ``model`` along ``run`` (see the module docstring).

    Parameters
    ----------
    run : a recording (``i`` optional).
    model : any model file.
    window, polyorder : Savitzky-Golay differentiator [samples]; None: ``DEFAULT_WINDOW_S``
        (20 ms) in samples of the run.
    force_gain : N/V for runs without current (else the sidecar's, else the model's loop).
    v_stick : stuck-speed threshold of the static friction model [m/s].
    """
    label = run_label(run)
    Ts = sample_time(run.time, label=label)
    if window is None:
        window = int(round(DEFAULT_WINDOW_S / Ts))
    w = odd_window(window, run.n)
    x_meas = np.asarray(run.x, dtype=float)
    xs = x_meas
    v, a, K = measured_motion(x_meas, Ts, w, polyorder)
    P = compile(model)
    v_f = friction_velocity(x_meas, Ts, w, polyorder) if P.prerolling else v
    F_motor, i, source = motor_force(run, P, xs, force_gain)
    F_load, _ = run_load(run)
    F_app = applied_force(F_motor, P.F_cg(xs), F_load, P.F_offset)
    F_f, stuck = model_friction(P, xs, v_f, F_app, Ts, v_stick)
    r = eq1_residual(F_app, F_f, a, P.m, K)
    c = P.compliance
    if c.on:
        if c.sensor_side != 0:
            raise ValueError(
                f"model {model.name!r}: compliance.sensor_side = {c.sensor_side}: the "
                "force residual needs the encoder on the slide (allowed 0)"
            )
        r = r - c.m2 * load_acceleration(a, Ts, c.f, c.zeta)
    start = None
    if P.prerolling:
        F_f, start, r = started_friction(xs, v_f, Ts, P.friction, r, K, F_f)
    if c.on:
        r = r - load_start_response(r, a, Ts, c.f, c.zeta)
    valid = np.isfinite(r)
    return RunResidual(
        name=run.name or label,
        Ts=Ts,
        K=K,
        time=np.asarray(run.time, float),
        x=xs,
        v=v,
        a=a,
        i=i,
        F_motor=F_motor,
        F_app=F_app,
        F_f=F_f,
        stuck=stuck,
        r=r,
        valid=valid,
        force_source=source,
        start=start,
        v_f=v_f,
        F_load=F_load,
        u=np.asarray(run.u, float),
        x_meas=x_meas,
    )


def residuals(runs: list[Run], model: ModelFile, **kw) -> list[RunResidual]:
    """:func:`force_residual` of every run."""
    return [force_residual(run, model, **kw) for run in runs]


def gap(res: list[RunResidual]) -> float:
    """The force gap: rms of r over every valid sample of every run [N]."""
    r = np.concatenate([q.r[q.valid] for q in res])
    return float(np.sqrt(np.mean(r**2)))
