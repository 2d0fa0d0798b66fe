"""Test harness: the 6 s closed loop (Sec. 3 sinusoid, state-space controller) as controller
FMU (FMI 2.0) + plant FMU stepped from Python, the plant either the FMI 2.0 FMU
(:func:`feeddrive.harness.two_fmus.simulate_two_fmus`) or the FMI 3.0 one with or without
early return / event mode at friction switches (:func:`two_fmus3`), on the same convention
(macro step Ts; at t_k x(t_k) -> x_meas, u(t_k) -> plant, both step over [t_k, t_k+1])."""

from __future__ import annotations

import ctypes
import time
from dataclasses import dataclass

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

from feeddrive.fmu3 import set_values
from feeddrive.harness.controller_fmu import (
    ControllerFMU,
    controller_fmu_parameters,
    sinusoid_source,
)
from feeddrive.harness.controllers import state_space_spec
from feeddrive.harness.references import sinusoid
from feeddrive.paper import paper_parameters

TS = 5e-4


@dataclass
class Loop3:
    """x at t_k (k = 0..n), and what the FMI 3.0 master saw."""

    x: np.ndarray
    early_returns: int  # fmi3DoStep calls that returned early (at a friction switch)
    events: int  # steps that asked for event mode (eventHandlingNeeded)
    do_steps: int  # fmi3DoStep calls in all
    switch_times: list[float]
    wall: float
    stats: dict  # the plant's stats.* at the end


def reference_6s() -> tuple[int, float, dict]:
    """n, x0 and the controller FMU's parameters of the 6 s, 30 mm sinusoid (bench.py's)."""
    ref = sinusoid(0.030, 6.0, 0.150, 6.0)
    values = controller_fmu_parameters(
        state_space_spec(), quantum=1e-7, reference=sinusoid_source(0.030, 6.0, 0.150, 6.0)
    )
    return ref.n, float(ref.x[0]), values


class _Controller3:
    """The FMI 3.0 controller FMU behind the calls the loop makes on the FMI 2.0 one."""

    def __init__(self, path: str, values: dict) -> None:
        md = read_model_description(path)
        self.var = {v.name: v for v in md.modelVariables}
        self.fmu = FMU3Slave(
            guid=md.guid,
            unzipDirectory=extract(path),
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName="ctrl3",
        )
        self.values = values

    def start(self, x0: float) -> float:
        self.fmu.instantiate()
        for name, value in {**self.values, "x_meas": x0}.items():
            v = self.var[name]
            getattr(self.fmu, "set" + v.type)([v.valueReference], [v._python_type(value)])
        self.fmu.enterInitializationMode(startTime=0.0)
        self.fmu.exitInitializationMode()
        return self.u()

    def u(self) -> float:
        return self.fmu.getFloat64([self.var["u"].valueReference])[0]

    def step(self, k: int, x_meas: float | None) -> float | None:
        u = None
        if x_meas is not None:
            self.fmu.setFloat64([self.var["x_meas"].valueReference], [x_meas])
            u = self.u()
        self.fmu.doStep(k * TS, TS)
        return u

    def close(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()


def two_fmus3(
    path: str,
    n: int,
    x0: float,
    ctrl_values: dict,
    early_return: bool = False,
    event_mode: bool = False,
    tolerance: float = 1e-6,
    controller3: str | None = None,
) -> Loop3:
    """The loop with the FMI 3.0 plant at ``path`` (a fresh instance, default friction.N) and
    the FMI 2.0 controller FMU, or the FMI 3.0 one at ``controller3``."""
    if controller3 is not None:
        return _loop(
            path, n, x0, _Controller3(controller3, ctrl_values), early_return, event_mode, tolerance
        )
    with ControllerFMU(ctrl_values) as ctrl:
        return _loop(path, n, x0, _Controller2(ctrl), early_return, event_mode, tolerance)


class _Controller2:
    """The FMI 2.0 controller FMU through its raw calls (as simulate_two_fmus)."""

    def __init__(self, ctrl: ControllerFMU) -> None:
        self.ctrl = ctrl

    def start(self, x0: float) -> float:
        self.ctrl.start({"x_meas": x0})
        self.r = self.ctrl.raw_calls()
        self.xm = (ctypes.c_uint * 1)(self.ctrl.vr("x_meas"))
        self.vu = (ctypes.c_uint * 1)(self.ctrl.vr("u"))
        self.buf = (ctypes.c_double * 1)()
        return float(self.ctrl.raw(["u", "x_meas"]).get()[0])

    def step(self, k: int, x_meas: float | None) -> float | None:
        r, u = self.r, None
        if x_meas is not None:
            self.buf[0] = x_meas
            r.set_real(r.component, self.xm, 1, ctypes.addressof(self.buf))
            r.get_real(r.component, self.vu, 1, ctypes.addressof(self.buf))
            u = self.buf[0]
        r.do_step(r.component, k * TS, TS, 1)
        return u

    def close(self) -> None:
        pass


def _loop(
    path: str, n: int, x0: float, ctrl, early_return: bool, event_mode: bool, tolerance: float
) -> Loop3:
    md = read_model_description(path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    plant = FMU3Slave(
        guid=md.guid,
        unzipDirectory=extract(path),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="plant3",
    )
    xs = np.empty(n + 1)
    n_early = n_events = n_steps = 0
    switches: list[float] = []
    wall0 = time.perf_counter()
    u = ctrl.start(x0)
    plant.instantiate(eventModeUsed=event_mode, earlyReturnAllowed=early_return)
    set_values(plant, md, {**paper_parameters(), "x": x0, "v": 0.0, "u": u, "F_ext": 0.0})
    plant.enterInitializationMode(tolerance=tolerance, startTime=0.0)
    plant.exitInitializationMode()
    if event_mode:
        plant.updateDiscreteStates()
        plant.enterStepMode()
    xs[0] = plant.getFloat64([vr["x"]])[0]
    for k in range(n):
        t = k * TS
        u = ctrl.step(k, xs[k] if k > 0 else None)
        if k > 0:
            plant.setFloat64([vr["u"]], [u])
        t_now, t_end = t, t + TS  # the FMI 2.0 loop's step end, to the bit
        while True:
            need, _, early, t_last = plant.doStep(t_now, TS if t_now == t else t_end - t_now)
            n_steps += 1
            if early:
                n_early += 1
                switches.append(t_last)
            if need:
                n_events += 1
                plant.enterEventMode()
                plant.updateDiscreteStates()
                plant.enterStepMode()
            if not early:
                break
            t_now = t_last
        xs[k + 1] = plant.getFloat64([vr["x"]])[0]
    wall = time.perf_counter() - wall0
    names = ["stats.n_stick", "stats.n_slip", "stats.n_state_events", "stats.n_steps"]
    stats = dict(zip(names, plant.getInt32([vr[s] for s in names]), strict=True))
    plant.terminate()
    plant.freeInstance()
    ctrl.close()
    return Loop3(xs, n_early, n_events, n_steps, switches, wall, stats)
