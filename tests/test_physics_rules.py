"""Every rule of fmu_src/models/plant/params.c fed to the FMU and to feeddrive.physics.compile: the same
verdict and the same message (single-value rules are logged by fmi2Set* with its name in
front; rules on the compiled set when initialisation ends)."""

from __future__ import annotations

import math

import pytest

from feeddrive.fmu import FMUError, Plant
from feeddrive.model_description import variables
from feeddrive.model_file import INTEGER_PARAMETERS, paper_model
from feeddrive.paper import paper_parameters
from feeddrive.physics import ParameterError, check_value, compile

PAPER = paper_parameters()
REALS = [n for n, v in PAPER.items() if not isinstance(v, bool) and n not in INTEGER_PARAMETERS]

#: (parameters, whether the FMU refuses them at fmi2Set* already)
SINGLE = [
    {"m": -16.1},
    {"m": 0.0},
    {"Ts": 0.0},
    {"Ts": -5e-4},
    {"friction.F_s": 0.0},
    {"friction.F_c": -1.0},
    {"friction.V_s": 0.0},
    {"friction.delta": -0.6},
    {"friction.sigma2": -7135.0},
    {"friction.C": 0.0},
    {"friction.nu[1]": -0.1},
    {"friction.nu[2]": 1.5},
    {"friction.k[3]": 0.0},
    {"friction.k[10]": -1.0},
    {"cogging.lambda[1]": 0.0},
    {"ripple.lambda[8]": -0.01},
    {"friction.N": 0},
    {"friction.N": 11},
    {"m": math.nan},
    {"friction.F_s": math.inf},
    {"friction.F_c": -math.inf},
    {"m": 0.1 + 0.2},
    {"friction_profile.n": 1},
    {"friction_profile.n": 17},
    {"friction_profile.c[3]": -0.95},
    {"friction_profile.c[16]": 4.5},
    {"friction_profile.x_start": math.nan},
    {"compliance.f": 10.0},
    {"compliance.f": 250.0},
    {"compliance.zeta": -0.1},
    {"compliance.m2": 0.0},
]
COMPILED = [
    {"friction.F_c": 30.0},
    {"friction.nu[5]": 0.713},  # sum(nu) = 1.33
    {"friction.N": 4},  # sum(nu_1..4) = 0.617
    {"current.a[1]": 1.5, "current.a[2]": -0.5},  # pole at z = 1
    {"current.a[1]": 2.1, "current.a[2]": -1.2},  # complex poles at |z| = 1.095
    {"current.a[1]": 0.2, "current.a[2]": 1.5},  # a real pole at z = -1.13
    {"current.a[1]": 0.0, "current.a[2]": 0.0, "current.a[3]": 1.2},  # |k_3| = 1.2
    {"stroke.x_min": 0.3, "stroke.x_max": 0.3},
    {"stroke.x_min": 0.2, "stroke.x_max": 0.1},
    {"effects.asymmetric_friction": True, "asymmetry.dF": -30.0},
    {"effects.asymmetric_friction": True, "asymmetry.dF": -26.1},  # F_s + dF = 0
    {"effects.asymmetric_friction": True, "asymmetry.dsigma2": -60.0},
    {"effects.asymmetric_friction": True, "effects.viscous": False, "asymmetry.dsigma2": -1.0},
    {
        "effects.asymmetric_friction": True,
        "effects.stribeck": False,
        "asymmetry.dF": -22.0,
    },  # F_c + dF < 0
    {"friction_profile.x_start": 0.2, "friction_profile.x_end": 0.2},
    {
        "effects.position_friction": True,
        "friction_profile.x_start": 0.2,
        "friction_profile.x_end": 0.1,
    },
]
ACCEPTED = [
    {"current.a[1]": 1.5, "current.a[2]": -0.6},  # poles 0.75 +- 0.19j: stable
    {"effects.asymmetric_friction": True, "effects.stribeck": False, "asymmetry.dF": -21.0},
    {},
    {"effects.prerolling": False, "friction.nu[5]": 0.713},  # sum(nu) only with GMS
    {"friction.nu[5]": 0.3839},
    {"friction.F_c": 26.1},
    {"friction.F_c": 0.0},
    {"effects.asymmetric_friction": True, "asymmetry.dF": -21.6},
    {"effects.asymmetric_friction": False, "asymmetry.dF": -100.0},
    {"friction.sigma2": 0.0, "friction.nu[1]": 0.17},
    {
        "effects.position_friction": True,
        "friction_profile.n": 2,
        "friction_profile.c[1]": -0.9,
        "friction_profile.c[2]": 4.0,
        "friction_profile.x_start": -0.05,
    },
]


def fmu_verdict(plant: Plant, values: dict) -> str | None:
    """None when the FMU accepts ``values`` (initialisation included), else what it logged."""
    plant.parameters = dict(values)
    try:
        plant.start()
    except FMUError:
        return plant.messages[-1]
    return None


def py_verdict(values: dict) -> str | None:
    try:
        compile(values)
    except ParameterError as e:
        return str(e)
    return None


@pytest.fixture(scope="module")
def plant(fmu_path):
    with Plant(path=fmu_path) as p:
        yield p


@pytest.mark.parametrize("values", SINGLE, ids=lambda v: ",".join(f"{k}={v[k]}" for k in v))
def test_single_value_rules_agree(plant, values):
    name = next(iter(values))
    fn = "fmi2SetInteger" if name in INTEGER_PARAMETERS else "fmi2SetReal"
    got = py_verdict(values)
    assert got is not None or values == {"m": 0.1 + 0.2}
    expect = fmu_verdict(plant, values)
    assert (expect is None) == (got is None)
    if got is not None:
        assert expect == f"{fn}: {got}"


@pytest.mark.parametrize("values", COMPILED, ids=lambda v: ",".join(f"{k}={v[k]}" for k in v))
def test_compiled_set_rules_agree(plant, values):
    got = py_verdict(values)
    assert got is not None
    assert fmu_verdict(plant, values) == got


@pytest.mark.parametrize("values", ACCEPTED, ids=lambda v: ",".join(f"{k}={v[k]}" for k in v))
def test_accepted_by_both(plant, values):
    assert py_verdict(values) is None
    assert fmu_verdict(plant, values) is None


def test_non_finite_message_and_unit_of_every_real_parameter(plant):
    """inf in every Real parameter: the message names it with the unit of modelDescription.xml."""
    for name in REALS:
        got = py_verdict({name: math.inf})
        assert got is not None and fmu_verdict(plant, {name: math.inf}) == f"fmi2SetReal: {got}"


def test_non_integer_element_count():
    """The FMI interface passes friction.N as Integer; a mapping can hold 2.5 (params.c text)."""
    with pytest.raises(
        ParameterError, match=r"^friction.N = 2.5 is not an integer: allowed 1..10$"
    ):
        compile({"friction.N": 2.5})


def test_non_integer_knot_count():
    with pytest.raises(
        ParameterError,
        match=r"^friction_profile.n = 3.5 is not an integer: "
        r"allowed 2..16$",
    ):
        compile({"friction_profile.n": 3.5})


def test_model_file_and_unknown_names():
    P = compile(paper_model())
    assert P.m == 16.1 and P.friction.nu[-1] == pytest.approx(0.383)
    with pytest.raises(KeyError, match=r"friction\.Fs"):
        compile({"friction.Fs": 1.0})


def _declared_ends() -> list[tuple[str, float]]:
    """Every parameter's declared min and max (modelDescription.xml), at and just beyond."""
    out = []
    for name, v in variables().items():
        if v.causality != "parameter" or v.kind == "Boolean" or name == "solver.tol":
            continue
        for end, outward in ((v.lo, -1.0), (v.hi, 1.0)):
            if math.isinf(end):
                continue
            beyond = (
                end + outward
                if v.kind == "Integer"
                else end + outward * max(abs(end) * 1e-6, 1e-300)
            )
            out.append((name, end))
            out.append((name, beyond))
    return out


def test_every_declared_end_same_verdict_and_message(plant):
    """At and beyond each end of every parameter's declared range the FMU's setter and
    `check_value` agree: both accept, or both refuse with the same message."""
    ends = _declared_ends()
    assert len(ends) > 150
    refused = 0
    for name, value in ends:
        fn = "fmi2SetInteger" if variables()[name].kind == "Integer" else "fmi2SetReal"
        try:
            check_value(name, value)
            got = None
        except ParameterError as e:
            got = str(e)
        logged = fmu_verdict(plant, {name: value})  # the set's message, or a whole-set rule's
        expect = logged if logged is not None and logged.startswith(fn + ": ") else None
        assert (expect is None) == (got is None), (name, value, expect, got)
        if got is not None:
            refused += 1
            assert expect == f"{fn}: {got}", (name, value)
    assert refused >= len(ends) // 2  # every beyond-the-end value at least
