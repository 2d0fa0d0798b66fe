"""Several axes -- each a controller FMU and a plant FMU -- stepped by one master at Ts: the
X-Y table of the circular test (two axes, four FMUs).

Each axis is :func:`~.two_fmus.simulate_two_fmus`'s loop, the reference given as the
controller FMU's inputs (``ref.source`` 0: ``x_ref``, ``v_ref``, ``a_ref`` of sample
k + ``zpetc.preview``, :func:`~.controller_fmu.preview_inputs`).  Sample convention (the
harness's, :func:`~.simulate.simulate_closed_loop`): at t_k the master reads every plant's
x(t_k), sets it as that axis's ``x_meas`` with the axis's reference inputs, reads u(t_k)
(from that x_meas, no extra delay), sets it on the plant and steps all FMUs over
[t_k, t_k+1].  u[0] is computed during the controller's initialisation from the start
values (x_meas = x0, the first reference inputs) and is the plant's start value of ``u``.
The axes are mechanically independent (an X-Y table on separate guides): the master couples
them only in time.
"""

from __future__ import annotations

import ctypes
import time
from collections.abc import Mapping, Sequence
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..fmu import FMUError, Plant, Result
from ..harness.controller_fmu import ControllerFMU, preview_inputs
from ..harness.references import Reference


@dataclass(frozen=True)
class AxisLoop:
    """One axis of the master: plant FMU parameters, controller FMU parameters (with
    ``ref.source`` 0), the axis's reference."""

    name: str
    plant: Mapping[str, Any]
    controller: Mapping[str, Any]
    reference: Reference


def _message(*fmus: Plant) -> str:
    msgs = [m for f in fmus for m in f.messages]
    return msgs[-1] if msgs else ""


class _Axis:
    """The FMI handles and buffers of one axis during a run."""

    def __init__(self, loop: AxisLoop, ctrl: ControllerFMU, plant: Plant, n: int) -> None:
        if int(loop.controller.get("ref.source", 0)) != 0:
            raise ValueError(
                f"axis {loop.name}: the master feeds the reference: the controller "
                f"needs ref.source 0"
            )
        if loop.reference.n < n:
            raise ValueError(
                f"axis {loop.name}: the reference has {loop.reference.n} samples, the run {n}"
            )
        preview = (
            int(loop.controller.get("zpetc.preview", 0)) if loop.controller.get("zpetc.on") else 0
        )
        xr, vr, ar = preview_inputs(loop.reference, preview)
        self.xr, self.vr, self.ar = xr.tolist(), vr.tolist(), ar.tolist()
        self.ctrl, self.plant = ctrl, plant
        x0 = float(loop.reference.x[0])
        ctrl.start({"x_meas": x0, "x_ref": self.xr[0], "v_ref": self.vr[0], "a_ref": self.ar[0]})
        u0 = float(ctrl.get(["u"])["u"])
        plant.start({"x": x0, "v": 0.0, "u": u0, "F_ext": 0.0}, t0=0.0)
        cr, pr = ctrl.raw_calls(), plant.raw_calls()
        self.cc, self.pc = cr.component, pr.component
        self.c_step, self.p_step = cr.do_step, pr.do_step
        self.c_get, self.c_set, self.p_get, self.p_set = (
            cr.get_real,
            cr.set_real,
            pr.get_real,
            pr.set_real,
        )
        self.vr_in = (ctypes.c_uint * 4)(
            *(ctrl.vr(v) for v in ("x_meas", "x_ref", "v_ref", "a_ref"))
        )
        self.vr_u_c = (ctypes.c_uint * 1)(ctrl.vr("u"))
        self.vr_u_p = (ctypes.c_uint * 1)(plant.vr("u"))
        self.vr_x = (ctypes.c_uint * 1)(plant.vr("x"))
        self.inp = (ctypes.c_double * 4)()
        self.xs = (ctypes.c_double * (n + 1))()
        self.us = (ctypes.c_double * (n + 1))()
        self.base_x, self.base_u = ctypes.addressof(self.xs), ctypes.addressof(self.us)
        self.us[0] = u0
        if self.p_get(self.pc, self.vr_x, 1, self.base_x) > 1:
            raise FMUError(f"axis {loop.name}: plant fmi2GetReal x: {_message(plant)}")


def simulate_axes(
    loops: Sequence[AxisLoop],
    n: int | None = None,
    Ts: float = 5e-4,
    tolerance: float = 1e-6,
    controller_path: str | Path | None = None,
    plant_path: str | Path | None = None,
) -> dict[str, Result]:
    """Run the axes n samples (default: the shortest reference); per axis a Result of time,
    x (the plant's, k = 0..n), u; each with the run's ``wall`` [s] (all axes together)."""
    if not loops:
        raise ValueError("simulate_axes: no axis")
    n = min(lp.reference.n for lp in loops) if n is None else int(n)
    for lp in loops:
        if float(lp.controller.get("Ts", Ts)) != Ts or lp.reference.Ts != Ts:
            raise ValueError(
                f"axis {lp.name}: controller Ts {lp.controller.get('Ts')} and "
                f"reference Ts {lp.reference.Ts} must be the master's {Ts}"
            )
    with ExitStack() as stack:
        wall0 = time.perf_counter()
        axes = []
        for lp in loops:
            ctrl = stack.enter_context(ControllerFMU(lp.controller, path=controller_path))
            plant = stack.enter_context(
                Plant(lp.plant, interface="cs", tolerance=tolerance, path=plant_path)
            )
            axes.append(_Axis(lp, ctrl, plant, n))
        for k in range(n):
            t = k * Ts
            for ax in axes:
                if k > 0:
                    inp = ax.inp
                    inp[0], inp[1], inp[2], inp[3] = ax.xs[k], ax.xr[k], ax.vr[k], ax.ar[k]
                    at = ax.base_u + 8 * k
                    if (
                        ax.c_set(ax.cc, ax.vr_in, 4, inp) > 1
                        or ax.c_get(ax.cc, ax.vr_u_c, 1, at) > 1
                        or ax.p_set(ax.pc, ax.vr_u_p, 1, at) > 1
                    ):
                        raise FMUError(f"exchange at t = {t}: {_message(ax.ctrl, ax.plant)}")
                if ax.c_step(ax.cc, t, Ts, 1) > 1 or ax.p_step(ax.pc, t, Ts, 1) > 1:
                    raise FMUError(f"fmi2DoStep at t = {t}: {_message(ax.ctrl, ax.plant)}")
                if ax.p_get(ax.pc, ax.vr_x, 1, ax.base_x + 8 * (k + 1)) > 1:
                    raise FMUError(f"plant fmi2GetReal x at t = {t + Ts}: {_message(ax.plant)}")
        wall = time.perf_counter() - wall0
        out = {}
        for lp, ax in zip(loops, axes, strict=True):
            ax.us[n] = ax.us[n - 1]
            out[lp.name] = Result(
                {
                    "time": np.arange(n + 1) * Ts,
                    "x": np.array(ax.xs),
                    "u": np.array(ax.us),
                    "wall": np.array(wall),
                }
            )
    return out
