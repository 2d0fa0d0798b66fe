"""Run the system files in existing engines: libcosim (``libcosimpy``: the OSP structure with
libcosim's worker pool, or the SSP package with the fixed step on the calling thread -- the
SSD's ``numWorkerThreads="0"``, the only place libcosim 0.11 reads a thread count), fmpy's
``simulate_ssp`` and the container FMU under fmpy's ``simulate_fmu``.  Each returns the
plant's ``x`` and the controller's ``u`` at t_k = k Ts, k = 0..n, as :class:`~..fmu.Result`,
plus ``wall`` [s] of the engine's run.

Convention: these engines step all FMUs over [t_k, t_k+1] and transfer the outputs *after*
the step (Jacobi).  The controller FMU's ``u`` read at t_k+1 is computed from the ``x_meas``
it holds, x(t_k); so the plant's ``u`` over [t_k+1, t_k+2] lags the harness's (which reads
x(t_k+1) first) by one macro step.  libcosim propagates the start values through the
connections during initialisation; fmpy's ``simulate_ssp`` starts every connector at 0.0
(the first macro step sees x_meas = 0 and u = 0) and does not apply the SSD's parameter
bindings itself (:func:`run_fmpy_ssp` reads the ``.ssv`` files and passes them, typed).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..fmu import Result

if TYPE_CHECKING:
    from libcosimpy.CosimLogging import CosimLogLevel

#: the SSP package's parameter sets, one per component
SSV_FILES = {"plant": "resources/plant.ssv", "controller": "resources/controller.ssv"}
#: libcosim's causality codes (``CosimVariableCausality``) its SSP loader binds values to
_INPUT, _PARAMETER = 0, 1


def _libcosim_run(execution, n: int, Ts: float, substeps: int = 10) -> Result:
    from libcosimpy.CosimObserver import CosimObserver  # optional: the test extra

    obs = CosimObserver.create_last_value()
    execution.add_observer(obs)
    idx = {s.name.decode(): s.index for s in execution.slave_infos()}
    vr = {}
    for comp, var in (("plant", "x"), ("controller", "u")):
        vr[comp] = next(
            v.reference for v in execution.slave_variables(idx[comp]) if v.name.decode() == var
        )
    xs, us = np.full(n + 1, np.nan), np.full(n + 1, np.nan)  # row 0: not observed before a step
    wall0 = time.perf_counter()
    for k in range(1, n + 1):
        if not execution.step(substeps):
            raise RuntimeError(f"libcosim: step {k} failed")
        xs[k] = obs.last_real_values(idx["plant"], [vr["plant"]])[0]
        us[k] = obs.last_real_values(idx["controller"], [vr["controller"]])[0]
    wall = time.perf_counter() - wall0
    return Result({"time": np.arange(n + 1) * Ts, "x": xs, "u": us, "wall": np.array(wall)})


def quiet_libcosim(level: CosimLogLevel | None = None) -> None:
    """libcosim's own log at ``level``, by default warning (libcosim's default, debug, prints
    every FMI call)."""
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    log_output_level(CosimLogLevel.WARNING if level is None else level)


def run_libcosim_osp(directory: str | Path, n: int, Ts: float, substeps: int = 10) -> Result:
    """libcosim on ``directory/OspSystemStructure.xml`` (fixed step, base step Ts), n steps."""
    from libcosimpy.CosimExecution import CosimExecution  # optional: the test extra

    quiet_libcosim()
    execution = CosimExecution.from_osp_config_file(str(directory))
    return _libcosim_run(execution, n, Ts, substeps)


def libcosim_ssp_execution(path: str | Path):
    """A libcosim execution of the SSP package ``path`` with the SSD's algorithm (fixed step,
    ``numWorkerThreads="0"``: every FMU steps on the calling thread).

    libcosim's SSP loader applies a component's parameter set to its parameters and inputs
    only (a warning for any other): the plant's start state ``x``, ``v`` is refused.  Those
    values, read from the package's ``.ssv`` files, become the execution's initial values,
    as the OSP loader sets every ``InitialValue``."""
    from fmpy.ssp.ssd import read_ssv
    from libcosimpy.CosimExecution import CosimExecution  # optional: the test extra
    from libcosimpy.CosimLogging import CosimLogLevel

    # the loader's warning for each refused value, which is set below: errors only
    quiet_libcosim(CosimLogLevel.ERROR)
    execution = CosimExecution.from_ssp_file(str(path))
    quiet_libcosim()
    setters = {
        "Real": execution.real_initial_value,
        "Integer": execution.integer_initial_value,
        "Boolean": execution.boolean_initial_value,
    }
    for info in execution.slave_infos():
        comp = info.name.decode()
        if comp not in SSV_FILES:
            continue
        refused = {
            v.name.decode(): v.reference
            for v in execution.slave_variables(info.index)
            if v.causality not in (_INPUT, _PARAMETER)
        }
        for p in read_ssv(str(path), resource=SSV_FILES[comp]).parameters:
            if p.name in refused and not setters[p.type](
                info.index, refused[p.name], _typed_value(p.type, p.value)
            ):
                raise RuntimeError(f"libcosim: initial value {comp}.{p.name} refused")
    return execution


def run_libcosim_ssp(path: str | Path, n: int, Ts: float, substeps: int = 10) -> Result:
    """libcosim on the SSP package ``path`` (its own fixed step, on the calling thread),
    n samples of Ts read every ``substeps`` macro steps."""
    return _libcosim_run(libcosim_ssp_execution(path), n, Ts, substeps)


def time_libcosim_ssp(path: str | Path, stop_time: float) -> float:
    """Wall time [s] of libcosim's ``simulate_until(stop_time)`` on the SSP package, no
    observer (execution creation not counted)."""
    return timed_simulate_until(libcosim_ssp_execution(path), stop_time)


def _typed_value(kind: str, literal: str) -> float | int | bool:
    if kind == "Boolean":
        return literal == "true"
    if kind in ("Integer", "Enumeration"):
        return int(literal)
    return float(literal)


def run_fmpy_ssp(path: str | Path, n: int, Ts: float, substeps: int = 10) -> Result:
    """fmpy's ``simulate_ssp`` on the package ``path``, macro step Ts/substeps, n samples.

    fmpy 0.3.32 ignores the components' ``ParameterBinding`` and compares a Boolean's
    literal with 0.0 (``"false"`` would be set true): the ``.ssv`` files are read with fmpy's
    ``read_ssv`` and passed as one parameter set, names prefixed by the component, values
    typed."""
    from fmpy.ssp.simulation import simulate_ssp
    from fmpy.ssp.ssd import ParameterSet, read_ssv

    merged = ParameterSet(name="closed_loop")
    for comp, res in SSV_FILES.items():
        for p in read_ssv(str(path), resource=res).parameters:
            p.name = f"{comp}.{p.name}"
            p.value = _typed_value(p.type, p.value)
            merged.parameters.append(p)
    wall0 = time.perf_counter()
    h = Ts / substeps
    out = simulate_ssp(
        str(path), stop_time=(n - 0.5 / substeps) * Ts, step_size=h, parameter_set=merged
    )
    wall = time.perf_counter() - wall0
    # row j is recorded after the step [t_j, t_j + h], stamped t_j: x, u at t_j + h
    rows = np.arange(substeps - 1, n * substeps, substeps)
    xs = np.concatenate([[np.nan], out["plant.x"][rows]])
    us = np.concatenate([[np.nan], out["controller.u"][rows]])
    return Result({"time": np.arange(n + 1) * Ts, "x": xs, "u": us, "wall": np.array(wall)})


def simulate_container(
    path: str | Path, n: int, Ts: float, output: Sequence[str] = ("x", "u")
) -> tuple[np.ndarray, float]:
    """fmpy's ``simulate_fmu`` on the container FMU ``path`` (step and output interval Ts), n
    steps, ``output`` recorded: the result and the wall time [s] of the call."""
    from fmpy import simulate_fmu

    wall0 = time.perf_counter()
    out = simulate_fmu(
        str(path), stop_time=n * Ts, step_size=Ts, output_interval=Ts, output=list(output)
    )
    return out, time.perf_counter() - wall0


def run_container(path: str | Path, n: int, Ts: float) -> Result:
    """fmpy's ``simulate_fmu`` on the container FMU ``path`` (output interval Ts), n steps."""
    out, wall = simulate_container(path, n, Ts)
    return Result(
        {
            "time": np.asarray(out["time"][: n + 1]),
            "x": np.asarray(out["x"][: n + 1]),
            "u": np.asarray(out["u"][: n + 1]),
            "wall": np.array(wall),
        }
    )


def timed_simulate_until(execution, stop_time: float) -> float:
    """Wall time [s] of a libcosim execution's ``simulate_until(stop_time)``."""
    wall0 = time.perf_counter()
    if not execution.simulate_until(int(round(stop_time * 1e9))):
        raise RuntimeError(f"libcosim: simulate_until({stop_time}) failed")
    return time.perf_counter() - wall0


def time_libcosim_osp(directory: str | Path, stop_time: float) -> float:
    """Wall time [s] of libcosim's ``simulate_until(stop_time)`` on the OSP structure, no
    observer (execution creation -- loading and instantiating the FMUs -- not counted)."""
    from libcosimpy.CosimExecution import CosimExecution  # optional: the test extra

    quiet_libcosim()
    return timed_simulate_until(CosimExecution.from_osp_config_file(str(directory)), stop_time)
