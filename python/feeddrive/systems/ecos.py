"""Ecos (``ecospy`` from PyPI: NTNU's co-simulation engine, libecosc, FMI 2.0 CS) runs the
plant FMU alone with sampled inputs and the closed loop of :class:`~.closed_loop.ClosedLoopSystem`.

Ecos's fixed-step algorithm is Jacobi, as libcosim's (:mod:`.engines`): every model steps
over [t, t+h], then the outputs are transferred.  Its clock is a double advanced by
``t += h`` (libcosim's: integer nanoseconds), so after 25 750 steps of 50 us it is 5e-13 s
past k h; both FMUs match a communication time to their sample instants within 1e-9 of the
elapsed time.  ``get_real`` after a step reads the values after the transfer: the
controller's ``u`` then already answers the new ``x_meas`` (the pending sample), so the
loop's ``u`` is read where the plant received it, ``plant::u``.

``ecospy`` 0.7.2 bundles ``libecosc.so`` linked against ``libtbb.so.12`` without declaring
it; the PyPI package ``tbb`` installs that library into the environment's ``lib/``, loaded
here before ``ecospy`` (:func:`load_ecospy`).
"""

from __future__ import annotations

import ctypes
import sys
import time
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType

import numpy as np

from ..fmu import Result
from .closed_loop import CONNECTIONS, ClosedLoopSystem

#: the TBB runtime libecosc.so needs (PyPI ``tbb`` installs it under sys.prefix/lib)
TBB = "libtbb.so.12"


def load_ecospy() -> ModuleType:
    """Import ``ecospy`` with its TBB runtime loaded first; ImportError names what is missing."""
    lib = Path(sys.prefix) / "lib" / TBB
    try:
        ctypes.CDLL(str(lib) if lib.is_file() else TBB, mode=ctypes.RTLD_GLOBAL)
    except OSError as e:
        raise ImportError(
            f"ecospy needs {TBB} (PyPI package tbb): not in {lib.parent} "
            f"nor on the library path ({e})"
        ) from e
    import ecospy  # optional: the test extra

    ecospy.EcosLib.set_log_level("warn")
    return ecospy


def _typed(v: float | int | bool) -> float | int | bool:
    return v if isinstance(v, (bool, int)) else float(v)


def run_ecos_plant(
    fmu: str | Path,
    t: np.ndarray,
    u: np.ndarray,
    start_values: Mapping[str, float],
    record: Sequence[str],
) -> Result:
    """The plant FMU alone in Ecos: step h = t[1] - t[0], ``u[k]`` set before the step from
    t_k, ``record`` read after each step (row k + 1; row 0 after initialisation)."""
    ecospy = load_ecospy()
    n = len(t) - 1
    ss = ecospy.EcosSimulationStructure()
    ss.add_model("plant", str(fmu))
    ss.add_parameter_set(
        "init", {f"plant::{k}": _typed(v) for k, v in {**start_values, "u": float(u[0])}.items()}
    )
    sim = ecospy.EcosSimulation(structure=ss, step_size=float(t[1] - t[0]))
    try:
        sim.init(parameter_set="init")
        names = [f"plant::{c}" for c in record]
        out = np.empty((n + 1, len(record)))
        out[0] = [sim.get_real(c) for c in names]
        for k in range(n):
            if k > 0:
                sim.set_real("plant::u", float(u[k]))
            sim.step()
            out[k + 1] = [sim.get_real(c) for c in names]
        sim.terminate()
    finally:
        sim.free()
        ss.free()
    return Result(
        {"time": np.asarray(t, dtype=float), **{c: out[:, j] for j, c in enumerate(record)}}
    )


@contextmanager
def _closed_loop(system: ClosedLoopSystem, substeps: int | None) -> Iterator:
    """An initialised Ecos simulation of ``system`` (structure built here: both FMUs, the two
    connections, every start value as the parameter set), macro step Ts/substeps."""
    ecospy = load_ecospy()
    ss = ecospy.EcosSimulationStructure()
    ss.add_model("plant", str(system.plant_fmu))
    ss.add_model("controller", str(system.controller_fmu))
    for a, av, b, bv in CONNECTIONS:
        ss.make_real_connection(f"{a}::{av}", f"{b}::{bv}")
    ss.add_parameter_set(
        "init",
        {
            f"{comp}::{k}": _typed(v)
            for comp, vals in system.start_values(jacobi=True).items()
            for k, v in vals.items()
        },
    )
    sim = ecospy.EcosSimulation(
        structure=ss, step_size=system.Ts / (substeps or system.jacobi_substeps)
    )
    try:
        sim.init(parameter_set="init")
        yield sim
        sim.terminate()
    finally:
        sim.free()
        ss.free()


def run_ecos(system: ClosedLoopSystem, substeps: int | None = None) -> Result:
    """The closed loop in Ecos, macro step Ts/substeps (default the system's Jacobi substeps);
    x and the plant's u at t_k = k Ts, k = 0..n (row 0: after initialisation)."""
    N = substeps or system.jacobi_substeps
    n = system.n
    xs, us = np.empty(n + 1), np.empty(n + 1)
    with _closed_loop(system, N) as sim:
        xs[0], us[0] = sim.get_real("plant::x"), sim.get_real("plant::u")
        wall0 = time.perf_counter()
        for k in range(1, n + 1):
            sim.step(N)
            xs[k], us[k] = sim.get_real("plant::x"), sim.get_real("plant::u")
        wall = time.perf_counter() - wall0
    return Result({"time": np.arange(n + 1) * system.Ts, "x": xs, "u": us, "wall": np.array(wall)})


def time_ecos(system: ClosedLoopSystem, substeps: int | None = None) -> float:
    """Wall time [s] of Ecos's ``step_until(stop_time)`` on the closed loop (nothing read)."""
    with _closed_loop(system, substeps) as sim:
        wall0 = time.perf_counter()
        sim.step_until(system.stop_time)
        return time.perf_counter() - wall0
