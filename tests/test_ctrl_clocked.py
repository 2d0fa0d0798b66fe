"""The zero-delay loop as FMI 3.0 allows it: the controller FMU as FMI 3.0 instantiated with
Event Mode, its periodic input clock ``tick`` given at every sample (enter Event Mode, set
x_meas, fmi3SetClock, fmi3UpdateDiscreteStates, read u, enter Step Mode), the plant stepped
first.  It is the harness's run to the bit (Sec. 3 sinusoid, 100 nm scale) for the state-space
controller with ``delay`` 0 and 1 (and with the plant FMU as FMI 3.0 too) and for an lti
controller; the clock's description and its
refusals are those of the FMI 3.0 standard."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave, fmi3Float64, fmi3IntervalQualifier, fmi3ValueReference
from fmpy.validation import validate_fmu

from feeddrive.fmu import FMUError, Plant
from feeddrive.fmu3 import set_values
from feeddrive.harness import (
    make_controller,
    pid_lti_spec,
    simulate_closed_loop,
    sinusoid,
    state_space_spec,
)
from feeddrive.harness.clocked_controller import ClockedController, simulate_clocked
from feeddrive.harness.controller_fmu import controller_fmu_parameters, sinusoid_source
from feeddrive.paper import paper_parameters

ROOT = Path(__file__).resolve().parents[1]
CTRL3 = ROOT / "build" / "DriveController3.fmu"
A, P, C = 0.030, 6.0, 0.150  #: the Sec. 3 sinusoid [m], [s], [m]


def _both(spec: dict, duration: float, plant_path: Path | None = None) -> tuple[dict, dict]:
    ref = sinusoid(A, P, C, duration)
    with Plant(paper_parameters(), interface="cs") as plant:
        h = simulate_closed_loop(
            plant, make_controller(spec, ref), ref.n, float(ref.x[0]), quantum=1e-7
        )
    values = controller_fmu_parameters(
        spec, reference=sinusoid_source(A, P, C, duration), quantum=1e-7
    )
    clocked = simulate_clocked(
        paper_parameters(),
        values,
        ref.n,
        float(ref.x[0]),
        controller_path=CTRL3,
        plant_path=plant_path,
    )
    return h, clocked


@pytest.mark.parametrize("delay", [0, 1])
def test_clocked_state_space_loop_is_the_harness_bit_for_bit(fmu_path, delay: int) -> None:
    """The 6 s loop, state-space controller, ``delay`` 0 (zero delay) and 1: x and u to the bit."""
    h, c = _both({**state_space_spec(), "delay": delay}, P)
    assert np.array_equal(c["x"], h["x_measured"])
    assert np.array_equal(c["u"], h["u"])


def test_both_fmus_fmi3_is_the_harness_bit_for_bit(fmu_path, fmu3_path) -> None:
    """The plant FMU as FMI 3.0 too (both FMUs FMI 3.0), 6 s, ``delay`` 0: x and u to the bit."""
    h, c = _both(state_space_spec(), P, plant_path=fmu3_path)
    assert np.array_equal(c["x"], h["x_measured"])
    assert np.array_equal(c["u"], h["u"])


def test_clocked_lti_loop_is_the_harness_bit_for_bit(fmu_path) -> None:
    """An lti controller (the PID as transfer function) over 1 s: x and u to the bit."""
    h, c = _both(pid_lti_spec(), 1.0)
    assert np.array_equal(c["x"], h["x_measured"])
    assert np.array_equal(c["u"], h["u"])


def test_zero_delay_differs_from_the_delayed_loop(fmu_path) -> None:
    """The clocked loop is not the one-sample-late loop: with ``delay`` 1 the run moves by the
    lag of one sample at the sinusoid's speed (far more than rounding, below a millimetre)."""
    _, c0 = _both(state_space_spec(), 0.3)
    _, c1 = _both({**state_space_spec(), "delay": 1}, 0.3)
    d = float(np.max(np.abs(c1["x"] - c0["x"])))
    assert 1e-8 < d < 1e-4


def test_clock_in_the_description(fmu_path) -> None:
    """``tick``: an input Clock, periodic with the interval the parameter Ts (fixed), the
    inputs and outputs clocked by it, Event Mode offered; fmpy's validation is clean."""
    assert validate_fmu(str(CTRL3)) == []
    md = read_model_description(str(CTRL3))
    var = {v.name: v for v in md.modelVariables}
    tick = var["tick"]
    assert (
        tick.type == "Clock" and tick.causality == "input" and tick.intervalVariability == "fixed"
    )
    assert md.coSimulation.hasEventMode and not md.coSimulation.mightReturnEarlyFromDoStep
    for name in ("x_ref", "v_ref", "a_ref", "x_meas", "u", "x_cmd", "u_ff", "r_x"):
        assert var[name].clocks == [tick], name


def _instance(log: list[str], event_mode: bool = True) -> tuple[FMU3Slave, dict]:
    md = read_model_description(str(CTRL3))
    fmu = FMU3Slave(
        guid=md.guid,
        unzipDirectory=extract(str(CTRL3)),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="clocked",
    )
    fmu.instantiate(
        eventModeUsed=event_mode, logMessage=lambda env, st, cat, msg: log.append(msg.decode())
    )
    fmu.enterInitializationMode(startTime=0.0)
    fmu.exitInitializationMode()
    return fmu, {v.name: v.valueReference for v in md.modelVariables}


def test_clock_refusals(fmu_path) -> None:
    """The clock set in Step Mode, Event Mode entered twice, Step Mode left with a tick not
    taken, a step past a tick not given, the tick set without Event Mode: each an error whose
    message names the function and the rule; the interval is Ts."""
    log: list[str] = []
    fmu, vr = _instance(log)
    fmu.setClock([vr["tick"]], [True])  # Event Mode after initialisation: the tick of t_0
    fmu.updateDiscreteStates()
    fmu.enterStepMode()
    with pytest.raises(FMICallException):
        fmu.setClock([vr["tick"]], [True])
    assert log[-1].startswith("fmi3SetClock: ") and "Event Mode only" in log[-1]
    with pytest.raises(FMICallException):
        fmu.doStep(0.0, 2 * 5e-4)
    assert log[-1].startswith("fmi3DoStep: ") and "passes the clock tick" in log[-1]
    fmu.doStep(0.0, 5e-4)
    fmu.enterEventMode()
    with pytest.raises(FMICallException):
        fmu.enterEventMode()
    assert log[-1].startswith("fmi3EnterEventMode: ") and "already" in log[-1]
    fmu.setClock([vr["tick"]], [True])
    with pytest.raises(FMICallException):
        fmu.enterStepMode()
    assert "fmi3UpdateDiscreteStates first" in log[-1]
    fmu.updateDiscreteStates()
    fmu.enterStepMode()
    vrs, iv, q = (
        (fmi3ValueReference * 1)(vr["tick"]),
        (fmi3Float64 * 1)(),
        (fmi3IntervalQualifier * 1)(),
    )
    fmu.getIntervalDecimal(vrs, iv, q)
    assert iv[0] == 5e-4
    fmu.terminate()
    fmu.freeInstance()
    log2: list[str] = []
    plain, vr = _instance(log2, event_mode=False)
    with pytest.raises(FMICallException):
        plain.setClock([vr["tick"]], [True])
    assert "eventModeUsed = false" in log2[-1]
    plain.freeInstance()


def test_controller_object_names_the_failure(fmu_path) -> None:
    """A tick the FMU refuses (x_meas not finite) raises FMUError with the FMU's message, not
    fmpy's bare status."""
    values = controller_fmu_parameters(
        state_space_spec(), reference=sinusoid_source(A, P, C, 0.1), quantum=1e-7
    )
    with ClockedController(values, CTRL3) as c:
        c.start(0.15)
        with pytest.raises(
            FMUError, match=r"controller tick at sample 1: fmi3SetFloat64: .*x_meas"
        ):
            c.tick(float("nan"))


def test_the_tick_sample_in_any_order_of_the_event_mode(fmu_path) -> None:
    """The sample of a tick comes from the inputs set at the tick, whatever the order inside
    the Event Mode: u read before fmi3UpdateDiscreteStates (clock active), u read after it, or
    a u read before the clock was set (from the old x_meas) then dropped -- 20 ticks with x_meas
    moving 1 um per tick give the same u to the bit, and u moves."""
    values = controller_fmu_parameters(
        state_space_spec(), reference=sinusoid_source(A, P, C, 0.1), quantum=0.0
    )
    x0 = float(sinusoid(A, P, C, 0.1).x[0])
    runs = []
    for order in ("get_then_update", "update_then_get", "early_get"):
        log: list[str] = []
        md = read_model_description(str(CTRL3))
        fmu = FMU3Slave(
            guid=md.guid,
            unzipDirectory=extract(str(CTRL3)),
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=order,
        )
        fmu.instantiate(
            eventModeUsed=True,
            logMessage=lambda env, st, cat, msg, log=log: log.append(msg.decode()),
        )
        vr = {v.name: v.valueReference for v in md.modelVariables}
        set_values(fmu, md, values)
        fmu.enterInitializationMode(startTime=0.0)
        fmu.exitInitializationMode()
        us = []
        for k in range(20):
            if k > 0:
                fmu.doStep((k - 1) * 5e-4, 5e-4)
                fmu.enterEventMode()
            if order == "early_get":
                fmu.getFloat64([vr["u"]])
            fmu.setClock([vr["tick"]], [True])
            fmu.setFloat64([vr["x_meas"]], [x0 - 1e-6 * k])
            if order == "get_then_update":
                us.append(fmu.getFloat64([vr["u"]])[0])
                fmu.updateDiscreteStates()
            else:
                fmu.updateDiscreteStates()
                us.append(fmu.getFloat64([vr["u"]])[0])
            fmu.enterStepMode()
        fmu.terminate()
        fmu.freeInstance()
        runs.append(us)
    assert runs[0] == runs[1] == runs[2], runs
    assert runs[0][19] != runs[0][1] and max(abs(u) for u in runs[0]) < 10.0  # moving, not clamped
