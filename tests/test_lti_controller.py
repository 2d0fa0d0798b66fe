"""The general linear controller (``lti``): replayed exactly (against scipy.signal's dlsim and
lfilter), the PID and PID-lead of the registry and a cascaded P-PI as LTI specs, the clamp
and the back-calculation anti-windup, bad specs named, and the round trip through a run's
sidecar."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy import signal

from feeddrive.control.lti import back_calculation_gain, rest_state, tf_to_ss
from feeddrive.data import load_run, write_run
from feeddrive.harness import (
    Sensors,
    cascade_lti_spec,
    closed_loop_run,
    controller_spec,
    lti_spec,
    make_controller,
    pid_lead_spec,
    pid_lti_spec,
    pid_spec,
    read_run_sidecar,
    sinusoid,
)
from feeddrive.harness.controllers import lti_realisation
from feeddrive.harness.references import from_positions
from feeddrive.model_file import paper_model
from feeddrive.validation.replay import validate

TS = 5e-4
N = 4000
#: float64 rounding of a few thousand samples of a loop whose output is a difference of
#: terms ~100x larger (absolute positions): a few 1e-13 of the output's range
REL = 5e-12


def _signals(seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """x_ref (a 2 Hz sinusoid about 0.15 m) and x_meas lagging it with noise, at rest together
    at the first sample."""
    t = np.arange(N) * TS
    rng = np.random.default_rng(seed)
    r = 0.15 + 0.01 * np.sin(2 * np.pi * 2 * t)
    y = 0.15 + 0.01 * np.sin(2 * np.pi * 2 * t - 0.3) + 1e-4 * rng.standard_normal(N)
    y[0] = r[0]
    return r, y


def _run(spec, r, y, u_ff=None):
    c = make_controller(spec, from_positions(r, TS), u_ff=u_ff)
    return np.array([c.step(float(y[k]), k) for k in range(len(y))])


def _rel(a, b):
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


SPECS = {
    "pid_tf": pid_lti_spec(TS, tf=2e-4, u_limit=1e9),
    "pid_lead_tf": pid_lti_spec(TS, tf=2e-4, lead=(40.0, 120.0), u_limit=1e9),
    # on the paper's drive: crossover 24 Hz, phase margin 31 deg, gain margin 9.3 dB, min|1+L| 0.47
    "cascade_tf": cascade_lti_spec(40.0, 30.0, 0.04, 600.0, TS, u_limit=1e9),
    "per_input_den": lti_spec(
        TS,
        num=[[2.0e3, -1.9e3], [-3.0e3, 2.8e3, 0.0]],
        den=[[1.0, -0.95], [1.0, -1.2, 0.35]],
        u_limit=1e9,
    ),
}


def _random_ss(n: int, seed: int = 3) -> dict:
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n))
    A *= 0.97 / max(abs(np.linalg.eigvals(A)))
    return lti_spec(
        TS,
        A=A,
        B=rng.standard_normal((n, 2)) * 1e3,
        C=rng.standard_normal((1, n)),
        D=[[400.0, -380.0]],
        u_limit=1e9,
        x0="zero",
    )


@pytest.mark.parametrize("name", [*SPECS, "state_space_8"])
def test_unsaturated_equals_dlsim(name):
    spec = SPECS[name] if name in SPECS else _random_ss(8)
    r, y = _signals()
    u = _run(spec, r, y)
    real = lti_realisation(spec)
    _, ud, _ = signal.dlsim(
        (real.A, real.B, real.C, real.D, TS), np.c_[r, y], x0=real.s0 + real.s0_r * r[0]
    )
    assert _rel(u, ud[:, 0]) < REL
    if "num" in spec and not np.any(real.s0_r):
        # the transfer functions themselves, each input's filtered on its own (lfilter from a
        # zero state, which is the rest state of a controller on the error x_ref - x_meas):
        # each part is ~100x their sum, so the tolerance is wider
        num, den = spec["num"], spec["den"]
        dens = den if np.ndim(den[0]) else [den, den]
        ul = sum(signal.lfilter(nm, dn, x) for nm, dn, x in zip(num, dens, (r, y), strict=True))
        assert _rel(u, ul) < 20 * REL


@pytest.mark.parametrize("lead", [None, (40.0, 120.0)])
@pytest.mark.parametrize("tf", [0.0, 2e-4])
def test_pid_and_pid_lead_as_lti(tf, lead):
    r, y = _signals(1)
    kw = {"tf": tf, "u_limit": 1e9}
    ref = pid_spec(**kw) if lead is None else pid_lead_spec(*lead, **kw)
    u_pid = _run(ref, r, y)
    u_lti = _run(pid_lti_spec(TS, lead=lead, **kw), r, y)
    assert _rel(u_lti, u_pid) < REL


def test_cascade_is_p_pi_with_velocity_filter():
    """The cascade written out by hand, sample by sample, gives the same u."""
    Kx, Kv, Ti, fv = 40.0, 30.0, 0.04, 600.0
    r, y = _signals(2)
    a = np.exp(-2 * np.pi * fv * TS)
    v, q, u = 0.0, 0.0, []
    for k in range(N):
        if k:
            v = a * v + (1 - a) * (y[k] - y[k - 1]) / TS
        e_v = Kx * (r[k] - y[k]) - v
        q += TS / Ti * e_v
        u.append(Kv * (e_v + q))
    # two algorithms: the hand loop on the error, the realisation on the absolute positions
    # (terms ~300x the output, velocity /Ts): their rounding differs by more than dlsim's
    assert _rel(_run(SPECS["cascade_tf"], r, y), np.array(u)) < 20 * REL


def test_clamp_and_back_calculation():
    r, y = _signals(3)
    y = y - 0.004  # a large error: clamped for long
    spec = dict(SPECS["pid_tf"], u_limit=10.0)
    u_free = _run(spec, r, y)
    assert np.max(np.abs(u_free)) == 10.0 and np.mean(np.abs(u_free) == 10.0) > 0.2
    # without anti-windup the state is the unclamped system's: its output, clamped, is u
    real = lti_realisation(spec)
    _, ud, _ = signal.dlsim((real.A, real.B, real.C, real.D, TS), np.c_[r, y])
    np.testing.assert_allclose(u_free, np.clip(ud[:, 0], -10, 10), rtol=0, atol=REL * 1e3)
    # with it, while clamped the state follows (A - L C) s + (B - L D) e + L u
    aw = dict(spec, anti_windup={"pole": 0.5})
    L = lti_realisation(aw).L
    assert np.allclose(np.linalg.eigvals(real.A - np.outer(L, real.C)), 0.5, atol=1e-6)
    c = make_controller(aw, from_positions(r, TS))
    s_prev = None
    for k in range(N):
        u = c.step(float(y[k]), k)
        s = np.array(c._s)
        if s_prev is not None and abs(u) == 10.0:
            e = np.array([r[k], y[k]])
            pred = (
                (real.A - np.outer(L, real.C)) @ s_prev + (real.B - np.outer(L, real.D)) @ e + L * u
            )
            np.testing.assert_allclose(s, pred, rtol=1e-9, atol=1e-9 * np.max(np.abs(s)))
        s_prev = s
    # and it winds up less: the clamped stretch after the error returns is shorter
    u_aw = _run(aw, r, y)
    assert np.sum(np.abs(u_aw) == 10.0) < np.sum(np.abs(u_free) == 10.0)


def test_back_calculation_gain_needs_an_observable_realisation():
    A = np.diag([1.0, 1.0])
    with pytest.raises(ValueError, match="not observable"):
        back_calculation_gain(A, [[1.0, 1.0]], 0.5)
    L = back_calculation_gain([[0.9, 0.1], [0.0, 0.8]], [[1.0, 0.0]], 0.2)
    assert np.allclose(
        np.linalg.eigvals(np.array([[0.9, 0.1], [0.0, 0.8]]) - np.outer(L, [1.0, 0.0])),
        0.2,
        atol=1e-7,
    )


def test_rest_state_starts_quiet():
    """At rest at x_ref[0] the output is constant from the first sample (the velocity filter
    sees no jump of the absolute position), 0 for the controllers on the error (their
    integrator starts empty)."""
    r = np.full(50, 0.15)
    for name, spec in SPECS.items():
        u = _run(spec, r, r)
        assert np.ptp(u) < 1e-9 * max(1.0, np.max(np.abs(u))), name
        if name != "per_input_den":
            assert np.max(np.abs(u)) < 1e-9, name
    A, B, C, D = tf_to_ss(SPECS["cascade_tf"]["num"], SPECS["cascade_tf"]["den"])
    s = rest_state(A, B, C, D) * 0.15
    np.testing.assert_allclose(A @ s + B @ [0.15, 0.15], s, atol=1e-12)


@pytest.mark.parametrize(
    "change,match",
    [
        ({"A": [[1.0]]}, "either A, B, C, D"),
        ({"num": [[1.0, 2.0, 3.0], [1.0]], "den": [1.0, 0.5]}, "not causal"),
        ({"num": [[1.0]], "den": [1.0]}, "num must be"),
        ({"Ts": 1e-3}, "not the sample time"),
        ({"anti_windup": "yes"}, "anti_windup"),
        ({"anti_windup": {"pole": 1.5}}, r"pole = 1.5"),
        ({"x0": "warm"}, "x0"),
        ({"u_limit": -1.0}, "u_limit"),
        ({"gain": 3.0}, "unknown key"),
    ],
)
def test_bad_lti_specs_are_named(change, match):
    spec = dict(SPECS["pid_tf"], **change)
    with pytest.raises(ValueError, match=match):
        make_controller(spec, from_positions(np.full(8, 0.15), TS))


def test_order_and_shapes_checked():
    ref = from_positions(np.full(8, 0.15), TS)
    with pytest.raises(ValueError, match="at most 8 states"):
        make_controller(_random_ss(9), ref)
    bad = _random_ss(3)
    bad["B"] = bad["B"][:2]
    with pytest.raises(ValueError, match=r"B has shape \(2, 2\), needs \(3, 2\)"):
        make_controller(bad, ref)
    bad = _random_ss(3)
    bad["A"][1][1] = float("nan")
    with pytest.raises(ValueError, match="A has a value that is not finite"):
        make_controller(bad, ref)


@pytest.mark.parametrize("name", ["pid_lead_tf", "cascade_tf"])
def test_round_trip_through_the_sidecar(name, tmp_path, fmu_path):
    """A closed-loop run made with an lti controller: its sidecar gives back the same spec
    and the same controller (bit for bit on the recorded positions), and validate replays it."""
    spec = dict(SPECS[name], u_limit=10.0, anti_windup={"pole": 0.3})
    params = paper_model().fmu_parameters()
    ref = sinusoid(0.005, 1.0, 0.15, 1.0)
    run, _ = closed_loop_run(
        params, spec, ref, Sensors(current_noise=0.0), experiment="lti_test", name=name
    )
    write_run(run, tmp_path / f"{name}.csv")
    back = load_run(tmp_path / f"{name}.csv")
    side = read_run_sidecar(back)
    assert side.note_line() is None and side.controller == json.loads(json.dumps(spec))
    c1 = make_controller(spec, ref)
    c2 = make_controller(side.controller, from_positions(back.x_ref, side.Ts))
    assert controller_spec(c2) == side.controller
    q = Sensors().quantise(back.x)
    assert [c1.step(float(x), k) for k, x in enumerate(q)] == [
        c2.step(float(x), k) for k, x in enumerate(q)
    ]
    rep = validate(back, paper_model(), side)
    # the replay is the run itself (same controller, plant and scale): x_sim - x_meas is the
    # scale's rounding of x_meas, at most half its 100 nm quantum
    assert rep.position is not None and rep.position.band <= 0.5e-7 * (1 + 1e-9), rep.text()
