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
from typing import Protocol

import numpy as np

from .fmu import OUTPUTS, FMUError, Plant, Result

RECORD = ("x", "v", "a", "i", "F_motor", "F_cogging", "F_friction", "K_f")


class Controller(Protocol):
    """What the closed loop needs of a controller."""

    def reset(self) -> None: ...

    def step(self, x_meas: float, k: int) -> float: ...


def quantise(x: float, quantum: float) -> float:
    """Linear-scale reading: ``x`` rounded to the scale's resolution (0 disables)."""
    return round(x / quantum) * quantum if quantum > 0 else x


class _Stepper:
    """Advance the FMU by one sample [t_k, t_k + dt] through either interface."""

    def __init__(self, plant: Plant, dt: float, t0: float) -> None:
        self.p = plant
        self.dt = dt
        self.t0 = t0
        self.n_state_events = 0
        self.n_time_events = 0
        self.n_calls = 0
        if plant.interface == "cs":
            self._do = plant.fmu._functions["fmi2DoStep"]
            self._c = plant.fmu.component
        else:
            self._init_me()

    # ---- model exchange with fmpy's CVode
    def _init_me(self) -> None:
        from fmpy.sundials import CVodeSolver

        fmu = self.p.fmu
        md = self.p.md

        class _NoInput:
            def apply(self, *a, **k):
                return None

        self._event_iteration()
        fmu.enterContinuousTimeMode()
        self.solver = CVodeSolver(
            nx=md.numberOfContinuousStates, nz=md.numberOfEventIndicators,
            get_x=fmu.getContinuousStates, set_x=fmu.setContinuousStates,
            get_dx=fmu.getDerivatives, get_z=fmu.getEventIndicators,
            get_nominals=fmu.getNominalsOfContinuousStates, set_time=fmu.setTime,
            input=_NoInput(), startTime=self.t0, maxStep=self.dt,
            relativeTolerance=self.p.tolerance, maxNumSteps=100000)

    def _event_iteration(self) -> None:
        fmu = self.p.fmu
        need = True
        while need:
            need, terminate, _, _, _, _ = fmu.newDiscreteStates()
            if terminate:
                raise FMUError("the FMU asked to terminate")

    def step(self, k: int) -> None:
        t = self.t0 + k * self.dt
        t_next = self.t0 + (k + 1) * self.dt
        if self.p.interface == "cs":
            if self._do(self._c, t, self.dt, 1) > 1:
                raise FMUError(f"fmi2DoStep at t = {t}: " + (self.p.messages[-1] if self.p.messages else ""))
            self.n_calls += 1
            return
        fmu = self.p.fmu
        if k > 0:  # the sample at t_k (inputs already set for this instant)
            fmu.enterEventMode()
            self._event_iteration()
            fmu.enterContinuousTimeMode()
            self.solver.reset(t)
            self.n_time_events += 1
        while t < t_next and not math.isclose(t, t_next, rel_tol=0, abs_tol=1e-12):
            state_event, _, t = self.solver.step(t, t_next)
            fmu.setTime(t)
            if state_event:
                self.n_state_events += 1
                fmu.enterEventMode()
                self._event_iteration()
                fmu.enterContinuousTimeMode()
                self.solver.reset(t)


def _align_current(sig: dict) -> None:
    """Rows come from the end of each step (left limit at t_{k+1}): move i back one row."""
    if "i" in sig and len(sig["i"]) > 1:
        i = sig["i"]
        sig["i"] = np.concatenate((i[1:], i[-1:]))
        if "F_motor" in sig and "K_f" in sig:
            sig["F_motor"] = sig["K_f"] * sig["i"]


def simulate_open_loop(plant: Plant, t: np.ndarray, u: np.ndarray | float = 0.0,
                       F_ext: np.ndarray | float = 0.0,
                       start_values: Mapping[str, float] | None = None,
                       record: Sequence[str] = RECORD) -> Result:
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
    stepper = _Stepper(plant, dt, float(t[0]))
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


def simulate_closed_loop(plant: Plant, controller: Controller, n: int, x0: float,
                         Ts: float = 5e-4, quantum: float = 1e-7,
                         F_ext: np.ndarray | float = 0.0,
                         record: Sequence[str] = RECORD,
                         progress: Callable[[int], None] | None = None) -> Result:
    """Close the loop: at each sample the controller reads the quantised position.

    Parameters
    ----------
    n : number of controller samples (the run lasts n Ts).
    x0 : initial position [m] (stage at rest).
    quantum : linear-scale resolution [m] (100 nm default; 0 for none).
    F_ext : external force per sample (or constant) [N].

    Returns time, u, x_meas and the recorded FMU variables at t_k, k = 0..n, and the wall
    time and event counts in ``meta`` entries ``wall``, ``state_events``.
    """
    F_ext = np.broadcast_to(np.asarray(F_ext, dtype=float), (n + 1,))
    controller.reset()
    u = np.empty(n + 1)
    xm = np.empty(n + 1)
    xm[0] = quantise(x0, quantum)
    u[0] = controller.step(xm[0], 0)
    wall0 = _time.perf_counter()
    plant.start({"x": x0, "v": 0.0, "u": float(u[0]), "F_ext": float(F_ext[0])}, t0=0.0)
    rec = plant.raw(["x"] + [r for r in record if r != "x"])
    names = ["x"] + [r for r in record if r != "x"]
    inp = plant.raw(["u", "F_ext"])
    stepper = _Stepper(plant, Ts, 0.0)
    m = len(names)
    big = (ctypes.c_double * ((n + 1) * m))()      # the FMU writes the outputs here directly
    get, c_get, vr_out = rec._get_to, rec._c, ctypes.addressof(rec.vr)
    base = ctypes.addressof(big)
    if get(c_get, vr_out, m, base) > 1:
        raise FMUError("fmi2GetReal failed: " + (plant.messages[-1] if plant.messages else ""))
    ubuf, set_in = inp.buf, inp._set
    c, vr_in = inp._c, inp.vr
    step = controller.step
    const_F = bool(np.all(F_ext == F_ext[0]))
    F_list = F_ext.tolist()
    ubuf[1] = F_list[0]
    cs = plant.interface == "cs"
    do_step = plant.fmu._functions["fmi2DoStep"] if cs else None
    row_bytes = 8 * m
    u_list = [0.0] * (n + 1)
    xm_list = [0.0] * (n + 1)
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
                raise FMUError(f"fmi2SetReal u = {uk} at t = {k * Ts}: "
                               + (plant.messages[-1] if plant.messages else ""))
        if cs:
            if do_step(c, k * Ts, Ts, 1) > 1:
                raise FMUError(f"fmi2DoStep at t = {k * Ts}: " + (plant.messages[-1] if plant.messages else ""))
        else:
            stepper.step(k)
        get(c_get, vr_out, m, base + (k + 1) * row_bytes)
        if progress is not None and k % 1000 == 0:
            progress(k)
    out = np.ctypeslib.as_array(big).reshape(n + 1, m)
    u[1:] = u_list[1:]
    xm[1:] = xm_list[1:]
    wall = _time.perf_counter() - wall0
    xm[n] = quantise(out[n, 0], quantum)
    u[n] = u[n - 1]
    sig = {"time": np.arange(n + 1) * Ts, "u": u, "x_meas": xm, "F_ext": np.array(F_ext)}
    sig.update({name: out[:, j].copy() for j, name in enumerate(names)})
    _align_current(sig)
    sig["wall"] = np.array(wall)
    st = plant.get(["stats.n_state_events", "stats.n_slip", "stats.n_stick", "stats.n_steps", "stats.n_rhs"])
    sig["state_events"] = np.array(st["stats.n_state_events"] if plant.interface == "cs"
                                   else stepper.n_state_events)
    for key in ("stats.n_slip", "stats.n_stick", "stats.n_steps", "stats.n_rhs"):
        sig[key] = np.array(st[key])
    return Result(sig)
