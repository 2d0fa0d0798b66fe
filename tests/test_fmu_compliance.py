"""Effect ``compliance`` in the FMU (fmu_src/physics/compliance.c) and its Python twin
(feeddrive.physics.compliance): a load m2 on a spring-damper on the slide.

- switched off, the load follows the slide exactly and the encoder reads x;
- the FMU's derivatives equal the Python mirror's to 1e-9 relative (model exchange, states
  set by hand, GMS elements stuck and slipping);
- with the slide held by static friction the load rings at the parameterised f and zeta
  (fit of the free oscillation: f within 1e-5, zeta within 1e-3 relative; 1 % and 5 % would
  do, the integrator at tolerance 1e-8 gives ~1e-8);
- co-simulation (DP45 with events) and model exchange (CVode) agree with the effect on within
  the 0.1 um of test_cs_agreement.py;
- ``compliance.sensor_side = 1`` moves the encoder to the load;
- a serialised state holds the two states (format version 2 and later).
"""

from __future__ import annotations

import ctypes
import math

import numpy as np
import pytest
from scipy.optimize import curve_fit

from feeddrive.fmu import DEFAULT_FMU, Plant
from feeddrive.harness import pid_spec, sinusoid
from feeddrive.harness.controllers import make_controller
from feeddrive.harness.simulate import simulate_closed_loop, simulate_open_loop
from feeddrive.physics import compile

pytestmark = [
    pytest.mark.skipif(not DEFAULT_FMU.is_file(), reason="build the FMU first: make fmu"),
    pytest.mark.usefixtures("fmu_path"),
]  # on both FMI versions (conftest)

DP = ctypes.POINTER(ctypes.c_double)
ON = {
    "effects.compliance": True,
    "compliance.m2": 2.0,
    "compliance.f": 40.0,
    "compliance.zeta": 0.05,
}


def _loop(
    params: dict,
    interface: str = "cs",
    duration: float = 0.6,
    quantum: float = 1e-7,
    tol: float = 1e-6,
):
    ref = sinusoid(0.01, 0.4, 0.15, duration)
    with Plant(params, interface=interface, tolerance=tol) as p:
        return simulate_closed_loop(
            p,
            make_controller(pid_spec(), ref),
            ref.n,
            float(ref.x[0]),
            Ts=ref.Ts,
            quantum=quantum,
            record=("x", "v", "F_friction", "x_measured", "x_load", "v_load", "compliance.dx"),
        )


def test_off_the_load_is_the_slide():
    r = _loop({})
    assert np.array_equal(r["x_measured"], r["x"])
    assert np.array_equal(r["x_load"], r["x"]) and np.array_equal(r["v_load"], r["v"])
    assert np.all(r["compliance.dx"] == 0.0)


def test_derivatives_agree_with_the_python_mirror():
    P = compile({**ON, "compliance.zeta": 0.2})
    c = P.compliance
    cases = [
        (0.15, 0.0, 0.0, 3e-6, -2e-4),
        (0.151, 0.02, 0.0, -8e-6, 1e-3),
        (0.149, -0.01, 0.0, 2e-5, 5e-3),
    ]
    with Plant({**ON, "compliance.zeta": 0.2}, interface="me") as p:
        p.start({"u": 0.4})
        p.update_discrete_states()
        p.fmu.enterContinuousTimeMode()
        md = p.md
        nx = md.numberOfContinuousStates
        names = [d.variable.derivative.name for d in md.derivatives]
        assert names[-2:] == ["compliance.dx", "compliance.dv"]
        for x, v, F1, q, w in cases:
            y = np.zeros(nx)
            y[0], y[1], y[2], y[-2], y[-1] = x, v, F1, q, w
            p.fmu.setContinuousStates(y.ctypes.data_as(DP), nx)
            dy = np.zeros(nx)
            p.get_derivatives(dy.ctypes.data_as(DP), nx)
            g = p.get(["F_motor", "F_cogging", "F_friction", "compliance.F", "a"])
            F = float(c.force(q, w))
            assert math.isclose(g["compliance.F"], F, rel_tol=1e-12)
            a = (g["F_motor"] - g["F_cogging"] - g["F_friction"] + F) / P.m
            assert math.isclose(dy[1], a, rel_tol=1e-9, abs_tol=1e-9 * abs(F) / P.m)
            _dq, dw = c.derivatives(q, w, dy[1])
            assert dy[-2] == w and math.isclose(dy[-1], float(dw), rel_tol=1e-9)
            assert math.isclose(float(dw), -F / c.m2 - dy[1], rel_tol=1e-12)


def _ringdown(f: float, zeta: float, T: float = 0.4) -> tuple[float, float]:
    """Free oscillation of the load with the slide stuck (static friction, no current; the
    spring starts at 2 N, with F_cg(0.15 m) = 17.5 N below F_s = 26.1 N): the fitted (f, zeta)
    of compliance.dx."""
    q0 = 2.0 / (2.0 * (2 * np.pi * f) ** 2)
    params = {**ON, "compliance.f": f, "compliance.zeta": zeta, "effects.prerolling": False}
    t = np.arange(int(T / 2.5e-4) + 1) * 2.5e-4
    with Plant(params, tolerance=1e-8) as p:
        r = simulate_open_loop(
            p,
            t,
            u=0.0,
            start_values={"x": 0.15, "compliance.dx": q0},
            record=("x", "v", "compliance.dx", "x_load"),
        )
    assert np.all(r["v"] == 0.0) and np.all(r["x"] == 0.15)  # the slide stays stuck

    def model(tt, A, fz, z, ph):
        wn = 2 * np.pi * fz
        return A * np.exp(-z * wn * tt) * np.cos(wn * np.sqrt(1 - z * z) * tt + ph)

    popt, _ = curve_fit(model, t, r["compliance.dx"], p0=[q0, f * 1.02, zeta * 1.1, 0.0])
    return float(popt[1]), float(popt[2])


@pytest.mark.parametrize("f, zeta", [(40.0, 0.05), (150.0, 0.2)])
def test_free_oscillation_has_the_parameterised_frequency_and_damping(f, zeta):
    fe, ze = _ringdown(f, zeta)
    # 1 % and 5 % would do; the DP45 at tolerance 1e-8 gives ~1e-8 (fit of 0.4 s)
    assert abs(fe / f - 1) < 1e-5, fe
    assert abs(ze / zeta - 1) < 1e-3, ze


def test_cs_and_me_agree_with_compliance_on():
    cs = _loop(ON, "cs", quantum=0.0)
    me = _loop(ON, "me", quantum=0.0, tol=1e-9)
    assert np.max(np.abs(cs["x"] - me["x"])) < 0.1e-6
    assert np.max(np.abs(cs["x_load"] - me["x_load"])) < 0.1e-6
    assert np.max(np.abs(cs["F_friction"] - me["F_friction"])) < 0.05
    # the load really moves against the slide: several micrometres in this run
    assert np.max(np.abs(cs["compliance.dx"])) > 1e-6


def test_sensor_on_the_load():
    r = _loop({**ON, "compliance.sensor_side": 1})
    assert np.array_equal(r["x_measured"], r["x_load"])
    assert np.max(np.abs(r["x_measured"] - r["x"])) > 1e-6
    # x_measured read alone (the states-only fast path of fmi2GetReal) is the load's position
    with Plant({**ON, "compliance.sensor_side": 1}) as p:
        p.start({"x": 0.15, "u": 1.0})
        alone, inp = p.raw(["x_measured"]), p.raw(["u"])
        for k in range(40):
            inp.set([1.0 if k < 20 else -1.0])
            p.do_step(k * 5e-4, 5e-4)
            xm = float(alone.get()[0])
            g = p.get(["x", "x_load"])
            assert xm == g["x_load"] and (k < 2 or xm != g["x"])


def test_serialised_state_holds_the_load():
    params = {**ON}
    ref = sinusoid(0.01, 0.4, 0.15, 0.3)
    with Plant(params) as p:
        p.start({"x": 0.14})
        raw = p.raw(["x", "compliance.dx", "compliance.dv"])
        u = 0.5 * np.sin(np.arange(800) * 0.02)
        inp = p.raw(["u"])
        for k in range(300):
            inp.set([u[k]])
            p.do_step(k * 5e-4, 5e-4)
        st = p.serialize_state(p.get_state())
        assert raw.get()[1] != 0.0
        tail = []
        for k in range(300, 400):
            inp.set([u[k]])
            p.do_step(k * 5e-4, 5e-4)
            tail.append(raw.get().copy())
        p.set_state(p.deserialize_state(st))
        again = []
        for k in range(300, 400):
            inp.set([u[k]])
            p.do_step(k * 5e-4, 5e-4)
            again.append(raw.get().copy())
    assert np.array_equal(np.array(tail), np.array(again))
    del ref


def test_cs_and_me_agree_with_compliance_and_static_friction():
    # stick (v := 0, the load keeps its velocity) and breakaway events with the load ringing
    params = {**ON, "effects.prerolling": False}
    cs = _loop(params, "cs", quantum=0.0)
    me = _loop(params, "me", quantum=0.0, tol=1e-9)
    assert np.max(np.abs(cs["x"] - me["x"])) < 0.1e-6
    assert np.max(np.abs(cs["x_load"] - me["x_load"])) < 0.1e-6
    assert cs["stats.n_stick"] > 0 and cs["stats.n_slip"] > 0  # the events happened
