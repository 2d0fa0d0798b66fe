"""Bad parameters, inputs and call sequences: fmi2Error with a message naming the variable,
its value and the allowed range; never a crash.  Raw fmpy FMU2Model / FMU2Slave calls with
a logger callback that captures the messages (as feeddrive.fmu builds it)."""
from __future__ import annotations

import ctypes
import math
import re
from collections.abc import Iterator

import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE,
                       fmi2EventInfo, fmi2Real)

from feeddrive.fmu import Plant

FMI2_ERROR = 3


class Raw:
    """One FMU instance at a time on a loaded library, with the messages it logged."""

    def __init__(self, interface: str) -> None:
        self.plant = Plant(interface=interface)
        self.fmu = self.plant.fmu
        self.messages: list[str] = []
        self._live = False

    def _log(self, env, name, status, category, message) -> None:
        self.messages.append(message.decode() if isinstance(message, bytes) else str(message))

    def fresh(self) -> "Raw":
        """Free the previous instance; instantiate a new one (state Instantiated)."""
        if self._live:     # (fmpy's freeInstance() would also unload the library)
            self.fmu.fmi2FreeInstance(self.fmu.component)
        self.messages = []
        cb = fmi2CallbackFunctions()
        self._cb_logger = fmi2CallbackLoggerTYPE(self._log)
        cb.logger = self._cb_logger
        cb.allocateMemory = defaultCallbacks.allocateMemory
        cb.freeMemory = defaultCallbacks.freeMemory
        self._cb = cb
        self.fmu.instantiate(loggingOn=False, callbacks=cb)
        self.fmu.setupExperiment(startTime=0.0)
        self._live = True
        return self

    def initialized(self) -> "Raw":
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        return self

    def vr(self, name: str) -> int:
        return self.plant.vr(name)

    def set(self, name: str, value: float) -> None:
        v = self.plant.vars[name]
        if v.type == "Real":
            self.fmu.setReal([v.valueReference], [value])
        elif v.type == "Integer":
            self.fmu.setInteger([v.valueReference], [int(value)])
        else:
            self.fmu.setBoolean([v.valueReference], [bool(value)])

    def close(self) -> None:
        if self._live:
            self.fmu.freeInstance()    # the instance, then the library
            self._live = False
        self.plant._instantiated = False
        self.plant.close()


@pytest.fixture(scope="module")
def me(fmu_path) -> Iterator[Raw]:
    r = Raw("me")
    yield r
    r.close()


@pytest.fixture(scope="module")
def cs(fmu_path) -> Iterator[Raw]:
    r = Raw("cs")
    yield r
    r.close()


def _fails(call, raw: Raw) -> str:
    """Run ``call``; it must raise fmpy's FMICallException with status fmi2Error.  Returns
    the last logged message."""
    with pytest.raises(FMICallException) as err:
        call()
    assert err.value.status == FMI2_ERROR
    assert raw.messages, "fmi2Error without a logged message"
    return raw.messages[-1]


def _names_value_and_range(msg: str, name: str, value: str | float, rng: str) -> None:
    """``msg`` names ``name``, states the value (text, or a number after "name = ") and
    the allowed range."""
    assert name in msg, msg
    if isinstance(value, str):
        assert value in msg, msg
    else:
        m = re.search(re.escape(name) + r" = (\S+)", msg)
        assert m and float(m.group(1)) == value, msg
    assert rng in msg, msg


# (variable, bad value, text of the allowed range)
SET_RULES = [
    ("m", 0.0, "(0, inf)"), ("m", -16.1, "(0, inf)"),
    ("friction.nu[2]", 1.5, "[0, 1]"), ("friction.nu[3]", -0.1, "[0, 1]"),
    ("friction.F_s", 0.0, "(0, inf)"), ("friction.F_s", -26.1, "(0, inf)"),
    ("friction.V_s", 0.0, "(0, inf)"), ("friction.V_s", -0.0031, "(0, inf)"),
    ("friction.delta", 0.0, "(0, inf)"), ("friction.delta", -0.6, "(0, inf)"),
    ("friction.k[1]", 0.0, "(0, inf)"), ("friction.k[5]", -87660.0, "(0, inf)"),
    ("friction.C", 0.0, "(0, inf)"), ("friction.C", -10.8, "(0, inf)"),
    ("Ts", 0.0, "(0, inf)"), ("Ts", -5e-4, "(0, inf)"),
    ("friction.N", 0, "[1, 10]"), ("friction.N", 11, "[1, 10]"),
]


@pytest.mark.parametrize("name, value, rng", SET_RULES)
def test_out_of_range_parameter(me: Raw, name: str, value: float, rng: str) -> None:
    me.fresh()
    msg = _fails(lambda: me.set(name, value), me)
    _names_value_and_range(msg, name, float(value), rng)


def test_rejected_value_is_not_kept(me: Raw) -> None:
    me.fresh()
    _fails(lambda: me.set("m", -1.0), me)
    me.fmu.reset()
    me.initialized()
    assert me.fmu.getReal([me.vr("m")])[0] == 16.1


def _all_reals(me: Raw, causality: tuple[str, ...]) -> list[str]:
    return [n for n, v in me.plant.vars.items() if v.type == "Real" and v.causality in causality]


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_parameter_or_input_rejected(me: Raw, bad: float) -> None:
    """Every Real parameter and input, before initialisation."""
    names = _all_reals(me, ("parameter", "input"))
    assert len(names) > 100
    me.fresh()
    for name in names:
        me.messages.clear()
        msg = _fails(lambda: me.set(name, bad), me)
        _names_value_and_range(msg, name, "not a finite number", "allowed values are finite")
        assert re.search(re.escape(name) + r" = -?(nan|inf)\b", msg, re.I), msg
        me.fmu.reset()
        me.fmu.setupExperiment(startTime=0.0)


@pytest.mark.parametrize("name", ["u", "F_ext"])
@pytest.mark.parametrize("bad", [math.nan, math.inf])
def test_non_finite_input_during_simulation(me: Raw, cs: Raw, name: str, bad: float) -> None:
    for raw in (me, cs):
        raw.fresh().initialized()
        if raw is me:
            raw.fmu.enterContinuousTimeMode()
        msg = _fails(lambda: raw.set(name, bad), raw)
        _names_value_and_range(msg, name, "not a finite number", "finite")


def test_sum_of_nu_outside_tolerance(me: Raw) -> None:
    """sum(nu) must be 1 within 1e-3: Table 3 as printed (nu_5 = 0.38, sum 0.997) is
    rejected at initialisation, 0.9995 accepted."""
    me.fresh()
    me.set("friction.nu[5]", 0.38)
    me.fmu.enterInitializationMode()
    msg = _fails(me.fmu.exitInitializationMode, me)
    _names_value_and_range(msg, "friction.nu[1..5]", "sum to 0.997", "1 +- 0.001")
    me.fresh()
    me.set("friction.nu[5]", 0.3825)
    me.initialized()                          # no exception


def test_coulomb_above_static(me: Raw) -> None:
    me.fresh()
    me.set("friction.F_c", 30.0)
    me.fmu.enterInitializationMode()
    msg = _fails(me.fmu.exitInitializationMode, me)
    _names_value_and_range(msg, "friction.F_c", 30.0, "[0, friction.F_s]")
    m = re.search(r"friction\.F_s = (\S+?):", msg)
    assert m and float(m.group(1)) == 26.1, msg


def test_non_finite_start_state(me: Raw) -> None:
    me.fresh()
    msg = _fails(lambda: me.set("x", math.nan), me)
    _names_value_and_range(msg, "x", "not a finite number", "finite")


# ------------------------------------------------------------------ call sequences

def test_get_derivatives_before_initialization(me: Raw) -> None:
    me.fresh()
    msg = _fails(lambda: me.fmu.getDerivatives((fmi2Real * 12)(), 12), me)
    assert "fmi2GetDerivatives" in msg and "Instantiated" in msg


def test_do_step_on_model_exchange_instance(me: Raw) -> None:
    me.fresh().initialized()
    do_step = me.fmu.dll.fmi2DoStep
    do_step.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_int]
    do_step.restype = ctypes.c_int
    assert do_step(me.fmu.component, 0.0, 1e-3, 1) == FMI2_ERROR
    assert "fmi2DoStep" in me.messages[-1] and "co-simulation" in me.messages[-1]


def test_new_discrete_states_in_continuous_time_mode(me: Raw) -> None:
    me.fresh().initialized()
    me.fmu.enterContinuousTimeMode()
    msg = _fails(lambda: me.fmu.newDiscreteStates(), me)
    assert "fmi2NewDiscreteStates" in msg and "ContinuousTimeMode" in msg


def test_model_exchange_call_on_co_simulation_instance(cs: Raw) -> None:
    cs.fresh().initialized()
    fn = cs.fmu.dll.fmi2NewDiscreteStates
    fn.argtypes = [ctypes.c_void_p, ctypes.POINTER(fmi2EventInfo)]
    fn.restype = ctypes.c_int
    info = fmi2EventInfo()
    assert fn(cs.fmu.component, ctypes.byref(info)) == FMI2_ERROR
    assert re.search(r"fmi2NewDiscreteStates.*model exchange", cs.messages[-1])


def test_do_step_before_initialization(cs: Raw) -> None:
    cs.fresh()
    msg = _fails(lambda: cs.fmu.doStep(0.0, 1e-3), cs)
    assert "fmi2DoStep" in msg and "Instantiated" in msg


def test_instance_survives_and_can_be_reset(me: Raw) -> None:
    """After an illegal call the library still works: reset, initialise, evaluate."""
    me.fresh()
    _fails(lambda: me.fmu.getDerivatives((fmi2Real * 12)(), 12), me)
    me.fmu.reset()
    me.fmu.setupExperiment(startTime=0.0)
    me.initialized()
    assert math.isfinite(me.fmu.getReal([me.vr("F_cogging")])[0])
