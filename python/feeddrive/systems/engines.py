"""Run the system files in existing engines: libcosim (``libcosimpy``: the OSP structure or the
SSP package, fixed-step algorithm), fmpy's ``simulate_ssp`` and the container FMU under fmpy's
``simulate_fmu``.  Each returns the plant's ``x`` and the controller's ``u`` at t_k = k Ts,
k = 0..n, as :class:`~..fmu.Result`, plus ``wall`` [s] of the engine's run.

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
from pathlib import Path

import numpy as np

from ..fmu import Result

#: the SSP package's parameter sets, one per component
SSV_FILES = {"plant": "resources/plant.ssv", "controller": "resources/controller.ssv"}


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


def quiet_libcosim() -> None:
    """libcosim's own log at warning level (its default, debug, prints every FMI call)."""
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    log_output_level(CosimLogLevel.WARNING)


def run_libcosim_osp(directory: str | Path, n: int, Ts: float, substeps: int = 10) -> Result:
    """libcosim on ``directory/OspSystemStructure.xml`` (fixed step, base step Ts), n steps."""
    from libcosimpy.CosimExecution import CosimExecution  # optional: the test extra

    quiet_libcosim()
    execution = CosimExecution.from_osp_config_file(str(directory))
    return _libcosim_run(execution, n, Ts, substeps)


def run_libcosim_ssp(path: str | Path, n: int, Ts: float, substeps: int = 10) -> Result:
    """libcosim on the SSP package ``path`` (fixed step Ts/substeps), n samples of Ts.

    libcosimpy 0.0.6 loads the package and connects it but does not apply the components'
    parameter bindings (inline or ``.ssv``): the FMUs run on their defaults.  Kept to show
    it; the OSP structure is the libcosim path."""
    from libcosimpy.CosimExecution import CosimExecution  # optional: the test extra

    quiet_libcosim()
    execution = CosimExecution.from_ssp_file(str(path), step_size=int(round(Ts / substeps * 1e9)))
    return _libcosim_run(execution, n, Ts, substeps)


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


def run_container(path: str | Path, n: int, Ts: float) -> Result:
    """fmpy's ``simulate_fmu`` on the container FMU ``path`` (output interval Ts), n steps."""
    from fmpy import simulate_fmu

    wall0 = time.perf_counter()
    out = simulate_fmu(
        str(path), stop_time=n * Ts, step_size=Ts, output_interval=Ts, output=["x", "u"]
    )
    wall = time.perf_counter() - wall0
    return Result(
        {
            "time": np.asarray(out["time"][: n + 1]),
            "x": np.asarray(out["x"][: n + 1]),
            "u": np.asarray(out["u"][: n + 1]),
            "wall": np.array(wall),
        }
    )


def time_libcosim_osp(directory: str | Path, stop_time: float) -> float:
    """Wall time [s] of libcosim's ``simulate_until(stop_time)`` on the OSP structure, no
    observer (execution creation -- loading and instantiating the FMUs -- not counted)."""
    from libcosimpy.CosimExecution import CosimExecution  # optional: the test extra

    quiet_libcosim()
    execution = CosimExecution.from_osp_config_file(str(directory))
    wall0 = time.perf_counter()
    if not execution.simulate_until(int(round(stop_time * 1e9))):
        raise RuntimeError(f"libcosim: simulate_until({stop_time}) failed")
    return time.perf_counter() - wall0
