"""Bad parameters, inputs and call sequences: fmi2Error / fmi3Error with a message naming the
variable, its value and the allowed range; never a crash.  On both builds of the plant (FMI
2.0 and FMI 3.0, the ``version`` parameter): raw fmpy FMU2Model / FMU2Slave calls with a
logger callback that captures the messages (as feeddrive.fmu builds it), and fmpy's
FMU3Model / FMU3Slave with a logMessage callback."""

from __future__ import annotations

import ctypes
import math
import re
from collections.abc import Iterator
from pathlib import Path

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    defaultCallbacks,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2EventInfo,
    fmi2Real,
)
from fmpy.fmi3 import FMU3Model, FMU3Slave, fmi3Boolean, fmi3Float64

from conftest import FMU3, VERSIONS
from feeddrive.fmu import FMUError, Plant

FMI_ERROR = 3
# the functions the call-sequence tests call, by version
FN = {
    "2.0": {
        "derivatives": "fmi2GetDerivatives",
        "do_step": "fmi2DoStep",
        "discrete": "fmi2NewDiscreteStates",
        "me_only": "fmi2NewDiscreteStates",
    },
    "3.0": {
        "derivatives": "fmi3GetContinuousStateDerivatives",
        "do_step": "fmi3DoStep",
        "discrete": "fmi3UpdateDiscreteStates",
        "me_only": "fmi3GetContinuousStates",
    },
}


class Raw:
    """One FMU instance at a time on a loaded library, with the messages it logged."""

    def __init__(self, interface: str, version: str = "2.0") -> None:
        self.version, self.interface = version, interface
        self.messages: list[str] = []
        self._live = False
        if version == "2.0":
            self.plant = Plant(interface=interface)
            self.fmu = self.plant.fmu
            self.vars = self.plant.vars
        else:
            self.md = read_model_description(str(FMU3))
            mi = self.md.modelExchange if interface == "me" else self.md.coSimulation
            cls = FMU3Model if interface == "me" else FMU3Slave
            self.fmu = cls(
                guid=self.md.guid,
                unzipDirectory=extract(str(FMU3)),
                modelIdentifier=mi.modelIdentifier,
                instanceName="raw3",
            )
            self.vars = {v.name: v for v in self.md.modelVariables}

    def _log(self, env, name, status, category, message) -> None:
        self.messages.append(message.decode() if isinstance(message, bytes) else str(message))

    def _log3(self, env, status, category, message) -> None:
        self.messages.append(message.decode() if isinstance(message, bytes) else str(message))

    def fresh(self) -> Raw:
        """Free the previous instance; instantiate a new one (state Instantiated)."""
        if self._live:  # (fmpy's freeInstance() would also unload the library)
            getattr(self.fmu, "fmi2FreeInstance" if self.version == "2.0" else "fmi3FreeInstance")(
                self.fmu.component
            )
        self.messages = []
        if self.version == "3.0":
            self.fmu.instantiate(logMessage=self._log3)
            self._live = True
            return self
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

    def enter_init(self) -> None:
        if self.version == "2.0":
            self.fmu.enterInitializationMode()
        else:
            self.fmu.enterInitializationMode(startTime=0.0)

    def initialized(self) -> Raw:
        self.enter_init()
        self.fmu.exitInitializationMode()
        return self

    def reset(self) -> None:
        """Back to Instantiated (FMI 2.0: and the experiment set up again)."""
        self.fmu.reset()
        if self.version == "2.0":
            self.fmu.setupExperiment(startTime=0.0)

    def vr(self, name: str) -> int:
        return self.vars[name].valueReference

    def get(self, name: str) -> float:
        return (self.fmu.getReal if self.version == "2.0" else self.fmu.getFloat64)(
            [self.vr(name)]
        )[0]

    def set(self, name: str, value: float) -> None:
        """Set one variable; FMI 3.0: an element ``a[k]`` of an array sets the whole array (the
        others at their start values), ``friction.N`` is set in Configuration Mode."""
        if self.version == "2.0":
            v = self.vars[name]
            if v.type == "Real":
                self.fmu.setReal([v.valueReference], [value])
            elif v.type == "Integer":
                self.fmu.setInteger([v.valueReference], [int(value)])
            else:
                self.fmu.setBoolean([v.valueReference], [bool(value)])
            return
        m = re.fullmatch(r"(.*)\[(\d+)\]", name)
        v = self.vars[m.group(1)] if m and m.group(1) in self.vars else self.vars[name]
        if v.shape:
            vals = [v._python_type(s) for s in str(v.start).split()]
            vals[int(m.group(2)) - 1 if m and v.name != name else 0] = value
        else:
            vals = [value]
        if v.causality == "structuralParameter":
            self.fmu.enterConfigurationMode()
        getattr(self.fmu, "set" + v.type)([v.valueReference], [v._python_type(x) for x in vals])
        if v.causality == "structuralParameter":
            self.fmu.exitConfigurationMode()

    def enter_ct(self) -> None:
        self.fmu.enterContinuousTimeMode()

    def derivatives(self) -> None:
        if self.version == "2.0":
            self.fmu.getDerivatives((fmi2Real * 12)(), 12)
        else:
            self.fmu.getContinuousStateDerivatives((fmi3Float64 * 7)(), 7)

    def discrete(self) -> None:
        (self.fmu.newDiscreteStates if self.version == "2.0" else self.fmu.updateDiscreteStates)()

    def raw_do_step(self) -> int:
        """fmiXDoStep(0, 1e-3) called through ctypes whatever the instance (its status)."""
        f = getattr(self.fmu.dll, FN[self.version]["do_step"])
        if self.version == "2.0":
            f.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, ctypes.c_int]
            f.restype = ctypes.c_int
            return f(self.fmu.component, 0.0, 1e-3, 1)
        b = [fmi3Boolean() for _ in range(3)]
        d = ctypes.c_double()
        f.argtypes = (
            [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, fmi3Boolean]
            + [ctypes.POINTER(fmi3Boolean)] * 3
            + [ctypes.POINTER(ctypes.c_double)]
        )
        f.restype = ctypes.c_int
        return f(self.fmu.component, 0.0, 1e-3, True, *map(ctypes.byref, b), ctypes.byref(d))

    def raw_me_call(self) -> int:
        """A model-exchange-only function through ctypes (its status)."""
        f = getattr(self.fmu.dll, FN[self.version]["me_only"])
        f.restype = ctypes.c_int
        if self.version == "2.0":
            f.argtypes = [ctypes.c_void_p, ctypes.POINTER(fmi2EventInfo)]
            info = fmi2EventInfo()
            return f(self.fmu.component, ctypes.byref(info))
        f.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_double), ctypes.c_size_t]
        x = (ctypes.c_double * 7)()
        return f(self.fmu.component, x, 7)

    def close(self) -> None:
        if self._live:
            self.fmu.freeInstance()  # the instance, then the library
            self._live = False
        if self.version == "2.0":
            self.plant._instantiated = False
            self.plant.close()


@pytest.fixture(scope="module", params=VERSIONS, ids=lambda v: f"fmi{v[0]}")
def version(request, fmu_path, fmu3_path) -> str:
    return request.param


@pytest.fixture(scope="module")
def me(version) -> Iterator[Raw]:
    r = Raw("me", version)
    yield r
    r.close()


@pytest.fixture(scope="module")
def cs(version) -> Iterator[Raw]:
    r = Raw("cs", version)
    yield r
    r.close()


def _fails(call, raw: Raw) -> str:
    """Run ``call``; it must raise fmpy's FMICallException with status fmi2Error / fmi3Error.
    Returns the last logged message."""
    with pytest.raises(FMICallException) as err:
        call()
    assert err.value.status == FMI_ERROR
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
    ("m", 0.0, "(0, inf)"),
    ("m", -16.1, "(0, inf)"),
    ("friction.nu[2]", 1.5, "[0, 1]"),
    ("friction.nu[3]", -0.1, "[0, 1]"),
    ("friction.F_s", 0.0, "(0, inf)"),
    ("friction.F_s", -26.1, "(0, inf)"),
    ("friction.V_s", 0.0, "(0, inf)"),
    ("friction.V_s", -0.0031, "(0, inf)"),
    ("friction.delta", 0.0, "(0, inf)"),
    ("friction.delta", -0.6, "(0, inf)"),
    ("friction.k[1]", 0.0, "(0, inf)"),
    ("friction.k[5]", -87660.0, "(0, inf)"),
    ("friction.C", 0.0, "(0, inf)"),
    ("friction.C", -10.8, "(0, inf)"),
    ("Ts", 0.0, "(0, inf)"),
    ("Ts", -5e-4, "(0, inf)"),
    ("friction.N", 0, "[1, 10]"),
    ("friction.N", 11, "[1, 10]"),
]


@pytest.mark.parametrize("name, value, rng", SET_RULES)
def test_out_of_range_parameter(me: Raw, name: str, value: float, rng: str) -> None:
    me.fresh()
    msg = _fails(lambda: me.set(name, value), me)
    _names_value_and_range(msg, name, float(value), rng)


def test_rejected_value_is_not_kept(me: Raw) -> None:
    me.fresh()
    _fails(lambda: me.set("m", -1.0), me)
    me.reset()
    me.initialized()
    assert me.get("m") == 16.1


def _all_reals(me: Raw, causality: tuple[str, ...]) -> list[str]:
    return [
        n for n, v in me.vars.items() if v.type in ("Real", "Float64") and v.causality in causality
    ]


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_parameter_or_input_rejected(me: Raw, bad: float) -> None:
    """Every Real parameter and input, before initialisation (FMI 3.0: an array's first
    element)."""
    names = _all_reals(me, ("parameter", "input"))
    assert len(names) > (100 if me.version == "2.0" else 80)
    me.fresh()
    for name in names:
        me.messages.clear()
        msg = _fails(lambda name=name: me.set(name, bad), me)
        _names_value_and_range(msg, name, "not a finite number", "allowed values are finite")
        assert re.search(re.escape(name) + r"(\[1\])? = -?(nan|inf)\b", msg, re.I), msg
        me.reset()


@pytest.mark.parametrize("name", ["u", "F_ext"])
@pytest.mark.parametrize("bad", [math.nan, math.inf])
def test_non_finite_input_during_simulation(me: Raw, cs: Raw, name: str, bad: float) -> None:
    for raw in (me, cs):
        raw.fresh().initialized()
        if raw is me:
            raw.enter_ct()
        msg = _fails(lambda raw=raw: raw.set(name, bad), raw)
        _names_value_and_range(msg, name, "not a finite number", "finite")


def test_sum_of_nu_outside_tolerance(me: Raw) -> None:
    """sum(nu) must be 1 within 1e-3: Table 3 as printed (nu_5 = 0.38, sum 0.997) is
    rejected at initialisation, 0.9995 accepted."""
    me.fresh()
    me.set("friction.nu[5]", 0.38)
    me.enter_init()
    msg = _fails(me.fmu.exitInitializationMode, me)
    _names_value_and_range(msg, "friction.nu[1..5]", "sum to 0.997", "1 +- 0.001")
    me.fresh()
    me.set("friction.nu[5]", 0.3825)
    me.initialized()  # no exception


def test_coulomb_above_static(me: Raw) -> None:
    me.fresh()
    me.set("friction.F_c", 30.0)
    me.enter_init()
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
    msg = _fails(me.derivatives, me)
    assert FN[me.version]["derivatives"] in msg and "Instantiated" in msg


def test_do_step_on_model_exchange_instance(me: Raw) -> None:
    me.fresh().initialized()
    assert me.raw_do_step() == FMI_ERROR
    assert FN[me.version]["do_step"] in me.messages[-1] and "co-simulation" in me.messages[-1]


def test_new_discrete_states_in_continuous_time_mode(me: Raw) -> None:
    me.fresh().initialized()
    me.enter_ct()
    msg = _fails(me.discrete, me)
    assert FN[me.version]["discrete"] in msg and "ContinuousTimeMode" in msg


def test_model_exchange_call_on_co_simulation_instance(cs: Raw) -> None:
    cs.fresh().initialized()
    assert cs.raw_me_call() == FMI_ERROR
    assert re.search(FN[cs.version]["me_only"] + r".*model exchange", cs.messages[-1])


def test_do_step_before_initialization(cs: Raw) -> None:
    cs.fresh()
    msg = _fails(lambda: cs.fmu.doStep(0.0, 1e-3), cs)
    assert FN[cs.version]["do_step"] in msg and "Instantiated" in msg


def test_instance_survives_and_can_be_reset(me: Raw) -> None:
    """After an illegal call the library still works: reset, initialise, evaluate."""
    me.fresh()
    _fails(me.derivatives, me)
    me.reset()
    me.initialized()
    assert math.isfinite(me.get("F_cogging"))


@pytest.mark.parametrize("version", VERSIONS)
def test_plant_start_refused_is_an_fmu_error(
    version: str, fmu2_path: Path, fmu3_path: Path
) -> None:
    """A call refused while Plant.start sets up the instance (here a negative tolerance: the
    FMU allows a finite tolerance > 0) is an FMUError with the FMU's message, not fmpy's bare
    Exception."""
    path = fmu2_path if version == "2.0" else fmu3_path
    plant = Plant(path=path, tolerance=-1.0)
    with pytest.raises(FMUError, match=r"tolerance = -1"):
        plant.start()
    plant.close()


@pytest.mark.parametrize("version", VERSIONS)
def test_step_past_stop_time_names_the_call_that_set_it(
    version: str, fmu2_path: Path, fmu3_path: Path
) -> None:
    """The stop time comes from fmi2SetupExperiment (FMI 2.0) or fmi3EnterInitializationMode
    (FMI 3.0); the refusal of a step past it names the call of the instance's version."""
    plant = Plant(path=fmu2_path if version == "2.0" else fmu3_path)
    plant.start(stop_time=0.01)
    setter = "fmi2SetupExperiment" if version == "2.0" else "fmi3EnterInitializationMode"
    with pytest.raises(FMUError, match=rf"passes the stopTime 0\.01 given to {setter}$"):
        plant.do_step(0.0, 0.02)
    plant.close()
