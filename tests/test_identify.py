"""Identification procedures on synthetic runs built from the model's own equations.

Every run carries 100 nm position quantisation and white current noise (fixed seeds).
Constant-speed, pre-rolling and C runs are kinematic (x(t) prescribed, i from Eq. 1); the
mass and C runs are simulated (RK4, current held over each 0.5 ms sample as in the FMU).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import lfilter

from feeddrive import paper
from feeddrive.data import Run
from feeddrive.harness.references import prbs
from feeddrive.identify import (
    dstft,
    fit_weights,
    identify_attraction,
    identify_current_loop,
    identify_mass,
    identify_position_maps,
    identify_prerolling,
    identify_stribeck,
    maxwell_slip,
)
from feeddrive.physics import position_maps as maps
from feeddrive.physics.friction_curves import steady_friction, stribeck_level

P = paper.paper_parameters()
TS = paper.TS
Q = 1e-7  # linear-scale resolution [m]
NU = np.array(paper.nu_defaults())
K = np.array(paper.TABLE3["k"]) / paper.MM
F_S = P["friction.F_s"]
STRIBECK = [
    P[k]
    for k in ("friction.F_s", "friction.F_c", "friction.V_s", "friction.delta", "friction.sigma2")
]


def quantise(x):
    return np.round(x / Q) * Q


def friction(v, p=P):
    F = steady_friction(v, *STRIBECK)
    dF, ds2 = p.get("asymmetry.dF", 0.0), p.get("asymmetry.dsigma2", 0.0)
    return np.where(v < 0, F - dF + ds2 * v, F)


def constant_speed_run(v, x0, x1, load, rng, p=P, noise=0.005, ramp=0.05, dwell=0.1):
    """Trapezoidal move x0 -> x1 at speed v with standstill at both ends (kinematic)."""
    L, s, acc = abs(x1 - x0), np.sign(x1 - x0), v / ramp
    T = L / v + ramp
    t = np.arange(0, T + 2 * dwell, TS)
    tm = np.clip(t - dwell, 0, T)
    d = np.where(
        tm < ramp,
        0.5 * acc * tm**2,
        np.where(
            tm < T - ramp, 0.5 * acc * ramp**2 + v * (tm - ramp), L - 0.5 * acc * (T - tm) ** 2
        ),
    )
    vel = np.where(tm < ramp, acc * tm, np.where(tm < T - ramp, v, acc * (T - tm)))
    moving = (t > dwell) & (t < dwell + T)
    a = np.where(tm < ramp, acc, np.where(tm < T - ramp, 0.0, -acc)) * moving
    x, vv = x0 + s * d, s * vel
    i = (p["m"] * s * a + maps.cogging(x, p) + friction(vv, p) + load) / maps.force_constant(x, p)
    i = i + noise * rng.standard_normal(len(t))
    return Run(time=t, u=i / 1.126, x=quantise(x), i=i, F_load=np.full(len(t), float(load)))


def _scalar_maps(p=P):
    """Fast scalar K_f, F_cg for the RK4 loops (same formulas as feeddrive.physics.position_maps)."""

    def make(name, n):
        c = [p[f"{name}.c[{k}]"] for k in range(n)]
        h = [
            (2 * math.pi / p[f"{name}.lambda[{j}]"], p[f"{name}.a[{j}]"], p[f"{name}.b[{j}]"])
            for j in range(1, 9)
            if p[f"{name}.a[{j}]"] or p[f"{name}.b[{j}]"]
        ]
        return lambda x: (
            sum(ck * x**k for k, ck in enumerate(c))
            + sum(a * math.cos(w * x) + b * math.sin(w * x) for w, a, b in h)
        )

    return make("ripple", 3), make("cogging", 4)


def simulate(i_ff, x0, v0, rng, G0=None, C=None, xref=None, noise=0.002, sub=2, Kp=6e5, Kv=6.7e3):
    """Eq. 1 by RK4, current held per sample.  Friction: Eq. 12 (C None) or the summed GMS
    slip dynamics dG/dt = C/S (S - G) (v > 0).  Optional PD on quantised x around xref."""
    kf, cog = _scalar_maps()
    Fs, Fc, Vs, dl, s2 = STRIBECK
    m = P["m"]

    def f(x, v, G, ik):
        if C is None:
            return (
                v,
                (
                    kf(x) * ik
                    - cog(x)
                    - math.copysign(Fc + (Fs - Fc) * math.exp(-(abs(v / Vs) ** dl)), v)
                    - s2 * v
                )
                / m,
                0.0,
            )
        assert v > 0, "the slip-phase test run must not stop"
        S = Fc + (Fs - Fc) * math.exp(-(abs(v / Vs) ** dl))
        if C == math.inf:  # no frictional lag: G = S(v)
            return v, (kf(x) * ik - cog(x) - S - s2 * v) / m, 0.0
        return v, (kf(x) * ik - cog(x) - G - s2 * v) / m, C / S * (S - G)

    n, h = len(i_ff), TS / sub
    X, I = np.empty(n), np.array(i_ff, dtype=float)
    x, v, G = x0, v0, (G0 or 0.0)
    vref = None if xref is None else np.gradient(xref, TS)
    for k in range(n):
        X[k] = x
        if xref is not None:
            xq = round(x / Q) * Q
            vq = (xq - round(X[k - 1] / Q) * Q) / TS if k else v0
            I[k] += (Kp * (xref[k] - xq) + Kv * (vref[k] - vq)) / P["ripple.c[0]"]
        ik = I[k]
        for _ in range(sub):
            k1 = f(x, v, G, ik)
            k2 = f(x + h / 2 * k1[0], v + h / 2 * k1[1], G + h / 2 * k1[2], ik)
            k3 = f(x + h / 2 * k2[0], v + h / 2 * k2[1], G + h / 2 * k2[2], ik)
            k4 = f(x + h * k3[0], v + h * k3[1], G + h * k3[2], ik)
            x += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            v += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
            G += h / 6 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2])
    return Run(
        time=np.arange(n) * TS, u=I / 1.126, x=quantise(X), i=I + noise * rng.standard_normal(n)
    )


def maxwell_force(x, k, W):
    """Independent Maxwell-slip (force form): F_i = clip(F_i + k_i dx, -W_i, W_i), virgin."""
    Fi, out, xp = np.zeros(len(k)), np.empty(len(x)), x[0]
    for n, xn in enumerate(x):
        Fi = np.clip(Fi + k * (xn - xp), -W, W)
        xp = xn
        out[n] = Fi.sum()
    return out


def prerolling_run(A, rng, period=2.0, periods=3, xc=0.15, noise=0.002, premove=0.0):
    """x = xc + A sin(2 pi t / period) from a virgin friction state, or after an unrecorded
    move of ``premove`` [m] into xc (the state at the first recorded sample is then not
    virgin, as after a hold against cogging)."""
    t = np.arange(int(periods * period / TS)) * TS
    w = 2 * np.pi / period
    x, a = xc + A * np.sin(w * t), -A * w * w * np.sin(w * t)
    pre = xc - premove * np.linspace(1.0, 0.0, 400, endpoint=False)
    F = maxwell_force(np.concatenate((pre, x)), K, NU * F_S)[len(pre) :]
    i = (P["m"] * a + maps.cogging(x, P) + F) / maps.force_constant(x, P)
    return Run(time=t, u=i / 1.126, x=quantise(x), i=i + noise * rng.standard_normal(len(t))), F


# --------------------------------------------------------------------------- current loop
def test_prbs_is_maximum_length_order_11():
    u = prbs(11, amplitude=0.5, offset=0.1)
    assert len(u) == 2047
    assert set(np.round(u, 12)) == {-0.4, 0.6}
    assert np.sum(u > 0.1) == 1024  # m-sequence: one more 1 than 0


def test_current_loop_recovers_eq2_and_picks_order_2():
    rng = np.random.default_rng(1)
    u = prbs(11, amplitude=1.0, periods=2)
    i = lfilter(paper.CURRENT_B, [1.0] + [-a for a in paper.CURRENT_A], u)
    run = Run(
        time=np.arange(len(u)) * TS,
        u=u,
        x=np.zeros(len(u)),
        i=i + 0.01 * rng.standard_normal(len(u)),
    )  # 1 % of the 1.1 A swing
    fit = identify_current_loop(run)
    assert (fit.order, fit.delay) == (2, 2)
    for name, true in (
        ("current.a[1]", 1.404),
        ("current.a[2]", -0.4938),
        ("current.b[2]", 0.057909),
        ("current.b[3]", 0.057909 * 0.7461),
    ):
        assert fit.parameters[name] == pytest.approx(true, rel=0.02), name
        assert fit.stderr[name] < 0.01 * abs(true)
    assert fit.parameters["current.b[0]"] == fit.parameters["current.a[3]"] == 0.0
    assert fit.dc_gain == pytest.approx(1.1260, rel=0.01)
    assert fit.pole_hz == pytest.approx([113, 113], rel=0.02)
    assert fit.pole_zeta == pytest.approx([0.99, 0.99], abs=0.01)
    first = fit.candidates[0]
    assert first.order == 1 and first.rms_validation > 3 * fit.rms_residual


def test_current_loop_needs_current_column():
    run = Run(time=np.arange(100) * TS, u=np.zeros(100), x=np.zeros(100), meta={"name": "prbs7"})
    with pytest.raises(ValueError, match=r"prbs7.*'i'"):
        identify_current_loop(run)


# --------------------------------------------------------------------- ripple and cogging
@pytest.fixture(scope="module")
def maps_fit():
    rng = np.random.default_rng(2)
    runs = [
        constant_speed_run(1e-3, a, b, load, rng)
        for load in (0.0, 54.9, 272.7)
        for a, b in ((0.0, 0.3), (0.3, 0.0))
    ]
    return identify_position_maps(runs)


@pytest.mark.parametrize("name", ["ripple", "cogging"])
def test_position_maps_recover_table1(maps_fit, name):
    x = maps_fit.samples.x
    assert x[0] < 1e-3 and x[-1] > 0.299 and np.allclose(np.diff(x), 1e-4)
    true = maps.evaluate(name, x, P)
    fit = getattr(maps_fit, name)
    err = np.sqrt(np.mean((fit(x) - true) ** 2))
    assert err < 0.02 * np.ptp(true)
    for j in (1, 2, 3):  # Fourier coefficients within 0.05 N(/A)
        for c in "ab":
            key = f"{name}.{c}[{j}]"
            assert fit.parameters[key] == pytest.approx(P[key], abs=0.05), key
    sampled = maps_fit.samples.K_f if name == "ripple" else maps_fit.samples.F_cg
    assert np.sqrt(np.mean((sampled - true) ** 2)) < 0.02 * np.ptp(true)  # Eqs. 4-5


def test_position_maps_ablation_hits_cogging_harder(maps_fit):
    cog, rip = maps_fit.cogging.increase_percent, maps_fit.ripple.increase_percent
    assert rip > 10  # the quadratic K_f drift is visible ...
    assert cog > 5 * rip  # ... but dropping F_cg's cubic costs far more


def test_position_maps_need_two_loads():
    rng = np.random.default_rng(3)
    runs = [
        constant_speed_run(5e-3, 0.0, 0.05, 0.0, rng),
        constant_speed_run(5e-3, 0.05, 0.0, 0.0, rng),
    ]
    with pytest.raises(ValueError, match="two distinct loads"):
        identify_position_maps(runs)


def test_runs_without_current_use_the_static_gain():
    rng = np.random.default_rng(12)
    runs = [
        constant_speed_run(5e-3, a, b, load, rng)
        for load in (0.0, 272.7)
        for a, b in ((0.0, 0.04), (0.04, 0.0))
    ]
    bare = [
        Run(time=r.time, u=r.u, x=r.x, F_load=r.F_load, meta={"name": f"emps{k}"})
        for k, r in enumerate(runs)
    ]  # the generator writes u = i / 1.126
    with pytest.raises(ValueError, match=r"emps0.*'i' is absent"):
        identify_position_maps(bare)
    with pytest.warns(UserWarning, match="static current-loop gain"):
        s = identify_position_maps(bare, dc_gain=1.126).samples
    ref = identify_position_maps(runs).samples
    assert s.K_f == pytest.approx(ref.K_f) and s.F_cg == pytest.approx(ref.F_cg)


# -------------------------------------------------------------------------------- DSTFT
def test_dstft_peaks_and_magnitudes(maps_fit):
    s = maps_fit.samples
    D = dstft(s.F_cg, x0=s.x[0])
    assert D.N == 750 and D.positions[0] == pytest.approx(s.x[0] + 0.0375, abs=1e-9)
    assert sorted(np.round(D.peaks(3) * 1e3, 3)) == [12.5, 18.75, 37.5]
    for j in (1, 2, 3):
        a, b = P[f"cogging.a[{j}]"], P[f"cogging.b[{j}]"]
        mag, ph = D.component(0.0375 / j)
        # |X|/N = |a + jb|/2 per side band; the cubic's leakage moves it by a few %
        assert np.median(mag) == pytest.approx(abs(a + 1j * b) / 2, rel=0.05)
        assert np.median(ph) == pytest.approx(np.arctan2(-b, a), abs=0.1)
        assert np.ptp(ph) < 0.2  # constant phase along the stroke
    z = D.zero_frequency()
    poly = sum(P[f"cogging.c[{k}]"] * D.positions**k for k in range(4))
    assert np.ptp(z) > 5 and np.max(np.abs(z - poly)) < 0.5  # drifting zero-frequency term


def test_dstft_extra_wavelength_of_25mm():
    x = np.arange(3000) * 1e-4
    y = 0.4 * np.cos(2 * np.pi * x / 0.025) + 0.3 * np.sin(2 * np.pi * x / 0.025)
    mag, ph = dstft(y).component(0.025)
    assert mag == pytest.approx(np.full_like(mag, 0.25), abs=1e-9)
    assert ph == pytest.approx(np.full_like(ph, np.arctan2(-0.3, 0.4)), abs=1e-9)


# ------------------------------------------------------------------------------ Stribeck
def _stribeck_runs(p, seed):
    rng = np.random.default_rng(seed)
    runs = []
    for v in np.geomspace(2e-4, 0.1, 12):
        L = min(max(3 * v, 2e-3), 0.1)
        runs += [
            constant_speed_run(v, 0.1, 0.1 + L, 0.0, rng, p),
            constant_speed_run(v, 0.1 + L, 0.1, 0.0, rng, p),
        ]
    return runs


def test_stribeck_recovers_table2():
    fit = identify_stribeck(_stribeck_runs(P, 4), P, P)
    tol = {
        "friction.F_s": 0.03,
        "friction.F_c": 0.03,
        "friction.V_s": 0.15,
        "friction.delta": 0.15,
        "friction.sigma2": 0.10,
    }
    for name, rel in tol.items():
        assert fit.parameters[name] == pytest.approx(P[name], rel=rel), name
        assert fit.stderr[name] < rel * P[name]
    assert fit.asymmetry["asymmetry.dF"] == pytest.approx(0.0, abs=0.1)


def test_stribeck_asymmetry():
    p = dict(P, **{"asymmetry.dF": 1.5, "asymmetry.dsigma2": 10.0})
    fit = identify_stribeck(_stribeck_runs(p, 5), P, P)
    assert fit.asymmetry["asymmetry.dF"] == pytest.approx(1.5, abs=0.1)
    assert fit.asymmetry["asymmetry.dsigma2"] == pytest.approx(10.0, abs=2.0)


# ---------------------------------------------------------------------------------- mass
@pytest.mark.parametrize("friction_model", ["known", "coulomb_viscous"])
def test_mass_from_open_loop_run(friction_model):
    t = np.arange(1000) * TS
    u = 0.6 + 0.5 * np.sin(2 * np.pi * 8 * t)
    i = lfilter(paper.CURRENT_B, [1.0] + [-a for a in paper.CURRENT_A], u)
    run = simulate(i, 0.02, 0.1, np.random.default_rng(6), noise=0.005)
    assert np.all(np.diff(run.x) >= 0) and run.x[-1] < 0.3
    fr = P if friction_model == "known" else "coulomb_viscous"
    fit = identify_mass(run, P, P, friction=fr)
    assert fit.parameters["m"] == pytest.approx(16.1, rel=0.01)
    if friction_model == "coulomb_viscous":
        assert fit.parameters["friction.F_c"] == pytest.approx(21.6, rel=0.05)
        assert fit.parameters["friction.sigma2"] == pytest.approx(54, rel=0.05)


def test_mass_current_timing_option():
    t = np.arange(1000) * TS
    u = 0.6 + 0.5 * np.sign(np.sin(2 * np.pi * 8 * t))  # current steps: timing matters
    i = lfilter(paper.CURRENT_B, [1.0] + [-a for a in paper.CURRENT_A], u)
    run = simulate(i, 0.02, 0.1, np.random.default_rng(13), noise=0.002)
    late = Run(time=run.time, u=run.u, x=run.x, i=np.concatenate(([run.i[0]], run.i[:-1])))
    m_held = identify_mass(run, P, P, friction=P).parameters["m"]
    m_late = identify_mass(late, P, P, friction=P, current_timing="held_previous").parameters["m"]
    m_wrong = identify_mass(late, P, P, friction=P).parameters["m"]
    assert m_held == pytest.approx(16.1, rel=2e-3) and m_late == pytest.approx(16.1, rel=2e-3)
    assert abs(m_wrong / 16.1 - 1) > 3 * abs(m_late / 16.1 - 1)
    with pytest.raises(ValueError, match="current_timing"):
        identify_mass(run, P, P, current_timing="late")


# ---------------------------------------------------------------------------- attraction
def _sweep_run(C, T, f0, seed):
    """Closed-loop sweep v = 6 +- 5 mm/s (never reversing) with GMS slip dynamics."""
    t = np.arange(int(T / TS)) * TS
    v0, v1, w = 6e-3, 5e-3, 2 * np.pi * f0
    xr = 0.05 + v0 * t + v1 / w * (1 - np.cos(w * t))
    v, a = v0 + v1 * np.sin(w * t), v1 * w * np.cos(w * t)
    i_ff = (P["m"] * a + maps.cogging(xr, P) + friction(v)) / maps.force_constant(xr, P)
    G0 = float(stribeck_level(v0, *STRIBECK[:4]))
    return simulate(i_ff, 0.05, v0, np.random.default_rng(seed), G0=G0, C=C, xref=xr)


def test_attraction_default_C():
    fit = identify_attraction(_sweep_run(1.08e4, 2.0, 4.0, 7), P, x_skip=0.0)
    assert fit.resolved
    assert fit.C == pytest.approx(1.08e4, rel=0.15)  # stated factor: 1.15
    assert fit.C_interval[0] < 1.08e4 < fit.C_interval[1]
    assert fit.C_resolvable_max > 5e4


def test_attraction_instantaneous_slip_gives_a_bound():
    fit = identify_attraction(_sweep_run(math.inf, 2.0, 4.0, 8), P, x_skip=0.0)
    assert not fit.resolved and "below resolution" in fit.message
    assert fit.parameters["friction.C"] == fit.C_lower > 2e4


def test_attraction_literal_C():
    fit = identify_attraction(_sweep_run(10.8, 8.0, 0.5, 9), P, x_skip=0.0)
    assert fit.resolved and fit.C == pytest.approx(10.8, rel=0.15)


# ---------------------------------------------------------------------------- pre-rolling
def test_maxwell_slip_hand_values():
    F, Phi = maxwell_slip(np.array([0.0, 0.5, 2.0, 1.0, -1.0, -0.5]), [1.0], [2.0])
    assert Phi[:, 0] == pytest.approx([0.0, 0.5, 1.0, 0.0, -1.0, -0.5])
    assert F == pytest.approx(2 * Phi[:, 0])


@pytest.mark.parametrize("premove", [0.0, -60e-6])
def test_prerolling_recovers_table3(premove):
    rng = np.random.default_rng(10)
    large, _ = prerolling_run(0.5e-3, rng, premove=premove)
    small, F_small = prerolling_run(80e-6, rng, premove=premove)
    fit = identify_prerolling(large, small, P, N=5, current_timing="sampled")
    assert np.all(fit.W >= 0) and fit.W.sum() == pytest.approx(F_S, rel=1e-9)
    assert fit.rms_relative < 0.03
    # the identified model along the small run, from the second reversal on, against the truth
    r0 = int(np.argmin(small.x[: int(2.0 / TS)]))  # second reversal (bottom, t = 3T/4)
    model, _ = maxwell_slip(small.x[r0:], fit.Delta, fit.W, phi0=-1.0)
    err = model - F_small[r0:]
    assert np.sqrt(np.mean((err - err.mean()) ** 2)) < 0.03 * F_S
    delta_true = NU * F_S / K
    assert fit.Delta[[0, 1, 2, 4]] == pytest.approx(delta_true[[0, 1, 2, 4]], rel=0.1)
    assert fit.nu[[0, 1, 2, 4]] == pytest.approx(NU[[0, 1, 2, 4]], abs=0.03)
    assert sum(fit.parameters[f"friction.nu[{j}]"] for j in range(1, 6)) == pytest.approx(1.0)


def test_prerolling_nnls_keeps_weights_positive_where_plain_ls_fails():
    rng = np.random.default_rng(11)
    segments = [
        (r.x, F + 0.05 * rng.standard_normal(len(F)), 0.0)  # virgin start
        for r, F in (prerolling_run(A, rng) for A in (0.5e-3, 80e-6))
    ]
    equal = np.linspace(20e-6, 114e-6, 5)  # equally spaced Delta_i as in [11]
    W_ls, _ = fit_weights(segments, equal, F_S, fit_offset=False, nonnegative=False)
    W_nn, off = fit_weights(segments, equal, F_S)
    assert W_ls.min() < -1.0  # the paper's observation
    assert W_nn.min() >= 0 and W_nn.sum() == pytest.approx(F_S)
    assert len(off) == 2
