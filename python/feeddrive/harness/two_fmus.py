"""The closed loop as two FMUs, controller FMU + plant FMU, stepped from Python.

Connections: plant ``x_measured`` -> controller ``x_meas`` (the controller FMU quantises it
at ``scale.quantum``), controller ``u`` -> plant ``u``.  Macro step = Ts, Gauss-Seidel with
the plant first: over [t_k, t_k+1] the plant steps holding u_k, the master reads x(t_k+1),
sets it as the controller's x_meas, steps the controller over [t_k, t_k+1] and reads u_k+1
(the controller FMU's sample at t_k+1 from that x_meas), which it sets on the plant.  No
input is set and read back at one instant in Step Mode (FMI 2.0/3.0 co-simulation), and the
loop is the harness's (:func:`~.simulate.simulate_closed_loop`) with the controller's own
``ctrl.delay``: u_k from x(t_k) with ``ctrl.delay`` 0.  u[0] is computed from x0 during the
controller's initialisation and is the plant's start value of ``u``.
"""

from __future__ import annotations

import ctypes
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..fmu import FMUError, Plant, Result
from .controller_fmu import ControllerFMU


def _fail(what: str, *fmus: Plant) -> FMUError:
    msgs = [m for f in fmus for m in f.messages]
    return FMUError(what + ": " + (msgs[-1] if msgs else ""))


def simulate_two_fmus(
    plant_params: Mapping[str, Any],
    ctrl_params: Mapping[str, Any],
    n: int,
    x0: float,
    Ts: float = 5e-4,
    F_ext: float = 0.0,
    controller_path: str | Path | None = None,
    plant_path: str | Path | None = None,
    tolerance: float = 1e-6,
) -> Result:
    """Run n samples; returns time, x (the plant's ``x_measured``, rows k = 0..n), u and
    ``wall`` [s].

    ``ctrl_params``: :func:`~.controller_fmu.controller_fmu_parameters` (with ``Ts``).
    """
    with (
        ControllerFMU(ctrl_params, path=controller_path) as ctrl,
        Plant(plant_params, interface="cs", tolerance=tolerance, path=plant_path) as plant,
    ):
        wall0 = time.perf_counter()  # from initialisation to the end (as the harness's)
        ctrl.start({"x_meas": float(x0)})
        u0 = float(ctrl.raw(["u"]).get()[0])
        plant.start({"x": float(x0), "v": 0.0, "u": u0, "F_ext": float(F_ext)}, t0=0.0)
        px = plant.raw(["x_measured"])
        cr, pr = ctrl.raw_calls(), plant.raw_calls()
        cc, pc = cr.component, pr.component
        c_step, p_step = cr.do_step, pr.do_step
        c_get, c_set, p_get, p_set = cr.get_real, cr.set_real, pr.get_real, pr.set_real
        vr_xm = (ctypes.c_uint * 1)(ctrl.vr("x_meas"))
        vr_u_c = (ctypes.c_uint * 1)(ctrl.vr("u"))
        vr_u_p = (ctypes.c_uint * 1)(plant.vr("u"))
        vr_x = px.vr
        xs = (ctypes.c_double * (n + 1))()
        us = (ctypes.c_double * (n + 1))()
        base_x, base_u = ctypes.addressof(xs), ctypes.addressof(us)
        if p_get(pc, vr_x, 1, base_x) > 1:
            raise _fail("plant fmi2GetReal x", plant)
        us[0] = u0
        for k in range(n):
            t = k * Ts
            if k > 0 and p_set(pc, vr_u_p, 1, base_u + 8 * k) > 1:
                raise _fail(f"plant fmi2SetReal u at t = {t}", plant)
            if p_step(pc, t, Ts, 1) > 1:
                raise _fail(f"plant fmi2DoStep at t = {t}", plant)
            if p_get(pc, vr_x, 1, base_x + 8 * (k + 1)) > 1:
                raise _fail(f"plant fmi2GetReal x at t = {t + Ts}", plant)
            if (
                c_set(cc, vr_xm, 1, base_x + 8 * (k + 1)) > 1
                or c_step(cc, t, Ts, 1) > 1
                or c_get(cc, vr_u_c, 1, base_u + 8 * (k + 1)) > 1
            ):
                raise _fail(f"controller at t = {t + Ts}", ctrl)
        us[n] = us[n - 1]
        wall = time.perf_counter() - wall0
    return Result(
        {
            "time": np.arange(n + 1) * Ts,
            "x": np.array(xs),
            "u": np.array(us),
            "wall": np.array(wall),
        }
    )
