"""The closed loop with the controller FMU as FMI 3.0 in Event Mode, its input clock ``tick``
given at every sample: the zero-delay loop as FMI 3.0 co-simulation allows it.

At t_k the master steps the plant (FMI 2.0, the harness's) over [t_k-1, t_k] holding u_k-1,
reads x(t_k), steps the controller to t_k (it takes no sample inside a step), enters its Event
Mode, activates ``tick`` (fmi3SetClock), sets x(t_k) as its ``x_meas`` and reads u_k (the
sample of t_k, computed from it) while the clock is active, fmi3UpdateDiscreteStates commits
the sample, and the master returns the controller to Step Mode.  u_k acts on the plant over
[t_k, t_k+1): no delay but the controller's own ``ctrl.delay``, the harness's run
(:func:`~.simulate.simulate_closed_loop`) to the bit.
The first tick is at t_0, in the Event Mode the controller enters after initialisation.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

from ..fmu import FMUError, Plant, Result
from ..fmu3 import set_values

DEFAULT_CONTROLLER3_FMU = Path(str(resources.files("feeddrive") / "DriveController3.fmu"))


class ClockedController:
    """The FMI 3.0 controller FMU instantiated with Event Mode: :meth:`start` initialises it
    and takes the sample of t_0, :meth:`tick` steps it to the next sample instant and takes
    that sample.  Use as a context manager (the instance is freed on exit)."""

    def __init__(self, ctrl_params: Mapping[str, Any], path: str | Path | None = None) -> None:
        path = str(path or DEFAULT_CONTROLLER3_FMU)
        self.md = read_model_description(path)
        if not self.md.coSimulation.hasEventMode:
            raise ValueError(
                f"{path}: the controller FMU has no Event Mode (hasEventMode is false)"
            )
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self._dir = extract(path)
        self.fmu = FMU3Slave(
            guid=self.md.guid,
            unzipDirectory=self._dir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName="controller",
        )
        self.params = dict(ctrl_params)
        self.Ts = float(self.params.get("Ts", 5e-4))
        self.k = 0
        self.messages: list[str] = []

    def __enter__(self) -> ClockedController:
        self.fmu.instantiate(
            eventModeUsed=True,
            logMessage=lambda env, st, cat, msg: self.messages.append(msg.decode()),
        )
        return self

    def __exit__(self, *exc: object) -> None:
        self.fmu.freeInstance()

    def _fail(self, what: str) -> FMUError:
        return FMUError(
            f"controller {what} at sample {self.k}: " + (self.messages[-1] if self.messages else "")
        )

    def _sample(self, x_meas: float) -> float:
        try:
            self.fmu.setClock([self.vr["tick"]], [True])
            self.fmu.setFloat64([self.vr["x_meas"]], [x_meas])
            u = self.fmu.getFloat64([self.vr["u"]])[
                0
            ]  # with the clock active (FMI 3.0 clocked variables)
            self.fmu.updateDiscreteStates()
            self.fmu.enterStepMode()
        except Exception:
            raise self._fail("tick") from None
        return u

    def start(self, x0: float, t0: float = 0.0) -> float:
        """Initialise at ``t0`` and take the sample of t_0 from ``x0``; u_0 [V]."""
        try:
            set_values(self.fmu, self.md, self.params)
            self.fmu.enterInitializationMode(startTime=t0)
            self.fmu.exitInitializationMode()  # into Event Mode: the tick of t_0
        except Exception:
            raise self._fail("initialisation") from None
        self.t0 = t0
        return self._sample(x0)

    def tick(self, x_meas: float) -> float:
        """Step from t_k to t_k+1 and take the sample of t_k+1 from ``x_meas``; u_k+1 [V]."""
        try:
            self.fmu.doStep(self.t0 + self.k * self.Ts, self.Ts)
            self.k += 1
            self.fmu.enterEventMode()
        except Exception:
            raise self._fail("step") from None
        return self._sample(x_meas)


def simulate_clocked(
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
    """Run n samples with the clocked FMI 3.0 controller; returns time, x (the plant's
    ``x_measured``, rows k = 0..n), u and ``wall`` [s], as
    :func:`~.two_fmus.simulate_two_fmus`.

    ``ctrl_params``: :func:`~.controller_fmu.controller_fmu_parameters` (with ``Ts``);
    ``plant_path``: the plant FMU, FMI 2.0 or 3.0 (default: the package's FMI 2.0 one).
    """
    xs = np.empty(n + 1)
    us = np.empty(n + 1)
    with (
        ClockedController({**ctrl_params, "Ts": Ts}, controller_path) as ctrl,
        Plant(plant_params, interface="cs", tolerance=tolerance, path=plant_path) as plant,
    ):
        wall0 = time.perf_counter()
        us[0] = ctrl.start(float(x0))
        plant.start({"x": float(x0), "v": 0.0, "u": float(us[0]), "F_ext": float(F_ext)}, t0=0.0)
        px = plant.raw(["x_measured"])
        pu = plant.raw(["u"])
        xs[0] = px.get()[0]
        for k in range(n):
            if k > 0:
                pu.set([us[k]])
            plant.do_step(k * Ts, Ts)
            xs[k + 1] = px.get()[0]
            us[k + 1] = ctrl.tick(float(xs[k + 1]))
        us[n] = us[n - 1]
        wall = time.perf_counter() - wall0
    return Result({"time": np.arange(n + 1) * Ts, "x": xs, "u": us, "wall": np.array(wall)})
