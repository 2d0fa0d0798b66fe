"""The engines' master algorithm, stepped from Python on the same two FMUs: the reference
against which the engines' runs are checked with *equal* conventions.

libcosim's fixed-step algorithm (and fmpy's ``simulate_ssp``, the container FMU): start
values set, initialisation propagates them through the connections (x_meas = x0, the plant's
u = the controller's u for x0); then per macro step h = Ts/jacobi_substeps: step every FMU over
[t, t+h], read every output, set every connected input (Jacobi).  Times as libcosim's
(integer nanoseconds, t = j h_ns / 1e9), so that the plant's integrator sees the same
floating-point times: with the 100 nm scale a last-bit difference in x can flip a
quantisation level and grow to micrometres.  The controller's u read at
t_k is thus computed from x(t_k - h): at h = Ts one sample of computation delay, the
harness's ``delay`` 1 with the files' ``ctrl.delay`` 0 (:mod:`.closed_loop`).
"""

from __future__ import annotations

import numpy as np

from ..fmu import FMUError, Plant, Result
from ..harness.controller_fmu import ControllerFMU
from .closed_loop import ClosedLoopSystem


def simulate_jacobi(system: ClosedLoopSystem) -> Result:
    """Run ``system`` with the Jacobi master; x, u at t_k = k Ts, k = 0..n (after the step)."""
    sv = system.start_values(jacobi=True)
    N, n = system.jacobi_substeps, system.n
    h_ns = int(round(system.jacobi_step * 1e9))  # libcosim's clock: integer nanoseconds
    h = h_ns / 1e9
    ctrl_par = {k: v for k, v in sv["controller"].items() if k != "x_meas"}
    plant_par = {k: v for k, v in sv["plant"].items() if k not in ("x", "v")}
    with (
        ControllerFMU(ctrl_par, path=system.controller_fmu) as ctrl,
        Plant(
            plant_par, interface="cs", tolerance=system.tolerance, path=system.plant_fmu
        ) as plant,
    ):
        ctrl.start({"x_meas": system.x0})
        u = float(ctrl.raw(["u"]).get()[0])
        plant.start({"x": system.x0, "v": 0.0, "u": u}, t0=0.0)
        cio, xm = ctrl.raw(["u"]), ctrl.raw(["x_meas"])
        pio, pu = plant.raw(["x"]), plant.raw(["u"])
        cr, pr = ctrl.raw_calls(), plant.raw_calls()
        xs, us = np.full(n + 1, np.nan), np.full(n + 1, np.nan)
        xs[0], us[0] = system.x0, u
        for j in range(n * N):
            t = j * h_ns / 1e9
            if cr.do_step(cr.component, t, h, 1) > 1 or pr.do_step(pr.component, t, h, 1) > 1:
                raise FMUError(
                    f"fmi2DoStep at t = {t}: " + ((ctrl.messages + plant.messages) or [""])[-1]
                )
            x, u = float(pio.get()[0]), float(cio.get()[0])
            xm.set((x,))
            pu.set((u,))
            if (j + 1) % N == 0:
                xs[(j + 1) // N], us[(j + 1) // N] = x, u
    return Result({"time": np.arange(n + 1) * system.Ts, "x": xs, "u": us})
