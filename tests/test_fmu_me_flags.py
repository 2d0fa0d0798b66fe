"""Model exchange event flags and log categories.

* fmi2NewDiscreteStates reports valuesOfContinuousStatesChanged = true at a current-loop
  sample (the current i jumps: the right-hand side is discontinuous), so an importer that
  keeps integrator history unless told (C fmusim's CVODE) restarts there.  It stays false at
  an event iteration without a sample or a switch.
* The per-sample trace is in ``logDebug``, which "all categories" (nCategories = 0) does
  not include; ``logEvents`` stays quiet over samples without a friction switch.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Model

pytestmark = pytest.mark.usefixtures("fmu_path")


def _events(fmu: Path, categories: list[str] | None) -> tuple[list[bool], list[str]]:
    """Start at rest, u = 0.5 V; ME event updates at t = 0, 1e-4 s (no sample) and Ts."""
    import fmpy.fmi2 as f2

    logged: list[str] = []

    def logger(env, name, status, category, message) -> None:
        logged.append(category.decode())

    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    cb = f2.fmi2CallbackFunctions()
    cb.logger = f2.fmi2CallbackLoggerTYPE(logger)
    cb.allocateMemory = f2.fmi2CallbackAllocateMemoryTYPE(f2.calloc)
    cb.freeMemory = f2.fmi2CallbackFreeMemoryTYPE(f2.free)
    m = FMU2Model(
        guid=md.guid,
        unzipDirectory=extract(str(fmu)),
        modelIdentifier=md.modelExchange.modelIdentifier,
        instanceName="flags",
    )
    m.instantiate(loggingOn=True, callbacks=cb)
    if categories is not None:
        m.setDebugLogging(True, categories)
    m.setupExperiment(startTime=0.0)
    m.enterInitializationMode()
    m.setReal([vr["u"]], [0.5])
    m.exitInitializationMode()
    flags = []
    Ts = float(next(v.start for v in md.modelVariables if v.name == "Ts"))
    for t in (None, 1e-4, Ts):
        if t is not None:
            m.enterContinuousTimeMode()
            m.setTime(t)
            m.enterEventMode()
        info = m.newDiscreteStates()
        flags.append(bool(info[3]))  # valuesOfContinuousStatesChanged
    m.terminate()
    m.freeInstance()
    return flags, logged


def test_sample_reports_states_changed(fmu_path) -> None:
    flags, _ = _events(fmu_path, None)
    assert flags[1] is False  # t = 1e-4 s: no sample, no switch
    assert flags[2] is True  # t = Ts: the current-loop sample, i jumps


def test_per_sample_trace_only_in_log_debug(fmu_path) -> None:
    _, default = _events(fmu_path, None)
    assert "logDebug" not in default and "logEvents" not in default
    _, debug = _events(fmu_path, ["logDebug"])
    assert "logDebug" in debug
