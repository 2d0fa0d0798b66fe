"""Run the plant FMU: open loop (input series) or closed loop (a controller at Ts).

Both interfaces of the FMU follow the same sample convention: the controller's output
u[k] is set at t_k = t0 + k Ts, before the FMU takes that instant's current-loop sample, and
is held until t_{k+1}.  u[0] is computed from the initial position before initialisation and
given as the start value of ``u`` (the drive is taken to have been holding it).

Recorded signals at row k are the FMU's values at t_k, except the sampled current: ``i[k]``
is Eq. 2's i[k], the current held over [t_k, t_{k+1}) (what the amplifier reports at sample
k), and ``F_motor[k] = K_f(x_k) i[k]``.
"""

from __future__ import annotations

import ctypes
import math
import time as _time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from fmpy.sundials import CVodeSolver

from ..fmu import FMUError, Plant, RawIO, Result
from .controllers import Controller

#: ``x_measured`` is what the encoder reads (``x`` unless the compliance's sensor is on the load)
RECORD = ("x", "v", "a", "i", "F_motor", "F_cogging", "F_friction", "K_f", "x_measured")
#: the variable the controller reads (quantised) each sample
MEASURED = "x_measured"
STATS = ("stats.n_state_events", "stats.n_slip", "stats.n_stick", "stats.n_steps", "stats.n_rhs")


def quantise(x: float, quantum: float) -> float:
    """Linear-scale reading: ``x`` rounded to the scale's resolution (0 disables)."""
    return round(x / quantum) * quantum if quantum > 0 else x


class _NoInput:
    """fmpy's CVode driver applies inputs through this; ours are set per sample."""

    def apply(self, *args: object, **kwargs: object) -> None:
        return None


class Stepper:
    """Advance the FMU by one sample [t_k, t_k + dt] through either interface (FMI 2.0 or
    3.0: the plant's calls of either version)."""

    def __init__(self, plant: Plant, dt: float, t0: float) -> None:
        self.p = plant
        self.dt = dt
        self.t0 = t0
        self.n_state_events = 0
        self.n_time_events = 0
        self.n_calls = 0
        if plant.interface == "cs":
            self._raw = plant.raw_calls()
        else:
            self._init_me()

    # ---- model exchange with fmpy's CVode
    def _init_me(self) -> None:
        fmu = self.p.fmu
        md = self.p.md
        self._event_iteration()
        fmu.enterContinuousTimeMode()
        self.solver = CVodeSolver(
            nx=md.numberOfContinuousStates,
            nz=md.numberOfEventIndicators,
            get_x=fmu.getContinuousStates,
            set_x=fmu.setContinuousStates,
            get_dx=self.p.derivatives(),
            get_z=fmu.getEventIndicators,
            get_nominals=fmu.getNominalsOfContinuousStates,
            set_time=fmu.setTime,
            input=_NoInput(),
            startTime=self.t0,
            maxStep=self.dt,
            relativeTolerance=self.p.tolerance,
            maxNumSteps=100000,
        )

    def _event_iteration(self) -> None:
        need = True
        while need:
            need, terminate, _, _, _, _ = self.p.update_discrete_states()
            if terminate:
                raise FMUError("the FMU asked to terminate")

    def _event(self, t: float) -> None:
        fmu = self.p.fmu
        fmu.enterEventMode()
        self._event_iteration()
        fmu.enterContinuousTimeMode()
        self.solver.reset(t)

    def step(self, k: int) -> None:
        """Integrate over [t_k, t_{k+1}] (inputs already set for t_k)."""
        t = self.t0 + k * self.dt
        t_next = self.t0 + (k + 1) * self.dt
        if self.p.interface == "cs":
            r = self._raw
            if r.do_step(r.component, t, self.dt, 1) > 1:
                raise FMUError(f"fmi2DoStep at t = {t}: " + _last_message(self.p))
            self.n_calls += 1
            return
        if k > 0:  # the sample at t_k is a time event
            self._event(t)
            self.n_time_events += 1
        while t < t_next and not math.isclose(t, t_next, rel_tol=0, abs_tol=1e-12):
            state_event, _, t = self.solver.step(t, t_next)
            self.p.fmu.setTime(t)
            if state_event:
                self.n_state_events += 1
                self._event(t)


def _last_message(plant: Plant) -> str:
    return plant.messages[-1] if plant.messages else ""


def _align_current(sig: dict[str, np.ndarray]) -> None:
    """Rows come from the end of each step (left limit at t_{k+1}): move i back one row."""
    if "i" in sig and len(sig["i"]) > 1:
        i = sig["i"]
        sig["i"] = np.concatenate((i[1:], i[-1:]))
        if "F_motor" in sig and "K_f" in sig:
            sig["F_motor"] = sig["K_f"] * sig["i"]


def simulate_open_loop(
    plant: Plant,
    t: np.ndarray,
    u: np.ndarray | float = 0.0,
    F_ext: np.ndarray | float = 0.0,
    start_values: Mapping[str, float] | None = None,
    record: Sequence[str] = RECORD,
) -> Result:
    """Drive the plant with sampled inputs held over each interval of the uniform grid ``t``.

    Returns the recorded variables at every grid point (t[0] is the initial state).
    """
    t = np.asarray(t, dtype=float)
    n = len(t)
    if n < 2:
        raise ValueError("t needs at least 2 points")
    dt = float(t[1] - t[0])
    if not np.allclose(np.diff(t), dt, rtol=1e-9, atol=1e-12):
        raise ValueError("t must be uniformly spaced")
    u = np.broadcast_to(np.asarray(u, dtype=float), (n,))
    F_ext = np.broadcast_to(np.asarray(F_ext, dtype=float), (n,))
    sv = dict(start_values or {})
    sv.update({"u": float(u[0]), "F_ext": float(F_ext[0])})
    plant.start(sv, t0=float(t[0]))
    rec = plant.raw(list(record))
    inp = plant.raw(["u", "F_ext"])
    stepper = Stepper(plant, dt, float(t[0]))
    out = np.empty((n, len(record)))
    out[0] = rec.get()
    for k in range(n - 1):
        if k > 0:
            inp.set((u[k], F_ext[k]))
        stepper.step(k)
        out[k + 1] = rec.get()
    sig = {"time": t.copy(), "u": np.array(u), "F_ext": np.array(F_ext)}
    sig.update({name: out[:, j].copy() for j, name in enumerate(record)})
    _align_current(sig)
    return Result(sig)


@dataclass
class _Loop:
    """The per-run state of :func:`simulate_closed_loop`: FMI handles and the buffers."""

    rec: RawIO  #: recorded variables, MEASURED ("x_measured") first
    inp: RawIO  #: u, F_ext
    stepper: Stepper
    out: ctypes.Array[ctypes.c_double]  #: (n + 1) x len(rec.names) doubles, written by the FMU
    u: list[float]
    x_meas: list[float]


def _start_loop(
    plant: Plant,
    controller: Controller,
    n: int,
    x0: float,
    quantum: float,
    F0: float,
    Ts: float,
    record: Sequence[str],
) -> _Loop:
    """Reset the controller, compute u[0] from the reading at x0, start the FMU holding it,
    and record row 0."""
    controller.reset()
    xm0 = quantise(x0, quantum)
    u0 = controller.step(xm0, 0)
    plant.start({"x": x0, "v": 0.0, "u": float(u0), "F_ext": F0}, t0=0.0)
    names = [MEASURED] + [r for r in record if r != MEASURED]
    rec = plant.raw(names)
    loop = _Loop(
        rec=rec,
        inp=plant.raw(["u", "F_ext"]),
        stepper=Stepper(plant, Ts, 0.0),
        out=(ctypes.c_double * ((n + 1) * len(names)))(),
        u=[0.0] * (n + 1),
        x_meas=[0.0] * (n + 1),
    )
    loop.u[0], loop.x_meas[0] = u0, xm0
    rec.get_into(ctypes.addressof(loop.out))
    return loop


def _sample_loop(
    plant: Plant,
    loop: _Loop,
    step: Callable[[float, int], float],
    n: int,
    Ts: float,
    quantum: float,
    F_ext: np.ndarray,
    progress: Callable[[int], None] | None,
) -> None:
    """The 2 kHz loop: read x_measured_k (the encoder's side), quantise, u_k = step(x_meas, k),
    set u (and F_ext), advance
    one sample, record row k + 1 (three FMI calls per sample through the CS interface)."""
    raw = loop.rec.calls
    c, get, set_in, do_step = raw.component, raw.get_real, raw.set_real, raw.do_step
    m = loop.rec.n
    big, base, row_bytes = loop.out, ctypes.addressof(loop.out), 8 * m
    vr_out, vr_in, ubuf = loop.rec.vr_address, loop.inp.vr, loop.inp.buf
    const_F = bool(np.all(F_ext == F_ext[0]))
    F_list = F_ext.tolist()
    ubuf[1] = F_list[0]
    cs = plant.interface == "cs"
    stepper = loop.stepper
    u_list, xm_list = loop.u, loop.x_meas
    for k in range(n):
        if k > 0:
            xk = big[k * m]
            xq = round(xk / quantum) * quantum if quantum > 0 else xk
            xm_list[k] = xq
            uk = step(xq, k)
            u_list[k] = uk
            ubuf[0] = uk
            if not const_F:
                ubuf[1] = F_list[k]
            if set_in(c, vr_in, 2, ubuf) > 1:
                raise FMUError(f"fmi2SetReal u = {uk} at t = {k * Ts}: " + _last_message(plant))
        if cs:
            if do_step(c, k * Ts, Ts, 1) > 1:
                raise FMUError(f"fmi2DoStep at t = {k * Ts}: " + _last_message(plant))
        else:
            stepper.step(k)
        if get(c, vr_out, m, base + (k + 1) * row_bytes) > 1:
            raise FMUError(f"fmi2GetReal at t = {(k + 1) * Ts}: " + _last_message(plant))
        if progress is not None and k % 1000 == 0:
            progress(k)


def _closed_loop_result(
    plant: Plant, loop: _Loop, n: int, Ts: float, quantum: float, F_ext: np.ndarray, wall: float
) -> Result:
    """The recorded signals (current aligned to Eq. 2's i[k]), wall time and FMU stats."""
    names = loop.rec.names
    out = np.ctypeslib.as_array(loop.out).reshape(n + 1, len(names))
    u = np.array(loop.u)
    xm = np.array(loop.x_meas)
    xm[n] = quantise(out[n, 0], quantum)
    u[n] = u[n - 1]
    sig = {"time": np.arange(n + 1) * Ts, "u": u, "x_meas": xm, "F_ext": np.array(F_ext)}
    sig.update({name: out[:, j].copy() for j, name in enumerate(names)})
    _align_current(sig)
    sig["wall"] = np.array(wall)
    st = plant.get(list(STATS))
    sig["state_events"] = np.array(
        st["stats.n_state_events"] if plant.interface == "cs" else loop.stepper.n_state_events
    )
    for key in STATS[1:]:
        sig[key] = np.array(st[key])
    return Result(sig)


def simulate_closed_loop(
    plant: Plant,
    controller: Controller,
    n: int,
    x0: float,
    Ts: float = 5e-4,
    quantum: float = 1e-7,
    F_ext: np.ndarray | float = 0.0,
    record: Sequence[str] = RECORD,
    progress: Callable[[int], None] | None = None,
) -> Result:
    """Close the loop: at each sample the controller reads the quantised position.

    Parameters
    ----------
    n : number of controller samples (the run lasts n Ts).
    x0 : initial position [m] (stage at rest).
    quantum : linear-scale resolution [m] (100 nm default; 0 for none).
    F_ext : external force per sample (or constant) [N].

    Returns
    -------
    dict
        time, u, x_meas and the recorded FMU variables at t_k, k = 0..n, and the wall
        time and event counts in entries ``wall``, ``state_events``, ``stats.*``.
    """
    F_ext = np.broadcast_to(np.asarray(F_ext, dtype=float), (n + 1,))
    wall0 = _time.perf_counter()
    loop = _start_loop(plant, controller, n, x0, quantum, float(F_ext[0]), Ts, record)
    _sample_loop(plant, loop, controller.step, n, Ts, quantum, F_ext, progress)
    return _closed_loop_result(plant, loop, n, Ts, quantum, F_ext, _time.perf_counter() - wall0)
