"""Frictional lag (Eq. 11): slipping elements relax toward nu_i s(v) with time constant S(|v|)/C.

Start: stage moving at v0 with every element at nu_i F_s (as just after a break-away at
low speed), held at v0 by a velocity loop.  With v constant, Eq. 11 integrates in closed
form:  sum F_i(t) = S(v0) + (F_s - S(v0)) exp(-C t / S(v0)).
"""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.physics.friction_curves import steady_friction, stribeck_level
from fmu_loops import FRICTION_ONLY, VelocityLoop, me_plant, run_law

pytestmark = pytest.mark.usefixtures("fmu_path")

V0 = 10e-3  # m/s: S(V0) = 22.20 N, F_s - S = 3.9 N


def _run(p: dict, C: float, lag: bool, dt: float, T: float):
    nu = [p[f"friction.nu[{j}]"] for j in range(1, 6)]
    # F_ext at t_0 balances the friction at t_0 (F_s + sigma2 v0); the loop takes over at t_1
    start = {"x": 0.0, "v": V0, "F_ext": -(p["friction.F_s"] + p["friction.sigma2"] * V0)}
    start.update({f"friction.F[{j}]": nu[j - 1] * p["friction.F_s"] for j in range(1, 6)})
    params = dict(
        FRICTION_ONLY,
        **{
            "friction.C": C,
            "effects.frictional_lag": lag,
            "stroke.x_min": -1.0,
            "stroke.x_max": 1.0,
        },
    )
    plant = me_plant(params)
    try:
        return run_law(plant, dt, int(round(T / dt)), VelocityLoop(lambda t: V0, p["m"], dt), start)
    finally:
        plant.close()


@pytest.mark.parametrize("C, dt", [(10.8, 5e-3), (1.08e4, 2e-5)])
def test_relaxation_time_is_S_over_C(paper: dict, C: float, dt: float) -> None:
    S = float(
        stribeck_level(
            V0,
            paper["friction.F_s"],
            paper["friction.F_c"],
            paper["friction.V_s"],
            paper["friction.delta"],
        )
    )
    tau = S / C
    run = _run(paper, C, True, dt, 2.0 * tau)
    t = run["time"]
    assert np.max(np.abs(run["v"] / V0 - 1.0)) < 1e-3  # speed held
    elem = run["F_friction"] - paper["friction.sigma2"] * run["v"]
    expected = S + (paper["friction.F_s"] - S) * np.exp(-t / tau)
    # 0.1 % of the relaxing part (F_s - S = 3.9 N); the speed varies by < 2e-4 relative,
    # which moves S(|v|) by < 1e-3 N
    assert np.max(np.abs(elem - expected)) < 1e-3 * (paper["friction.F_s"] - S)
    # the time constant itself, from a log-linear fit over [0.1, 2] tau: within 0.2 %
    m = t > 0.1 * tau
    slope = np.polyfit(t[m], np.log(elem[m] - S), 1)[0]
    assert -1.0 / slope == pytest.approx(tau, rel=2e-3)
    assert run.stats["stats.n_slip"] == 0 and np.all(run["n_stuck"] == 0)  # slipping from t = 0


def test_lag_off_follows_stribeck_at_once(paper: dict) -> None:
    """effects.frictional_lag = false: the element forces are nu_i s(v) from the start."""
    run = _run(paper, 10.8, False, 5e-3, 0.5)
    expected = steady_friction(
        run["v"],
        paper["friction.F_s"],
        paper["friction.F_c"],
        paper["friction.V_s"],
        paper["friction.delta"],
        paper["friction.sigma2"],
    )
    assert np.max(np.abs(run["F_friction"] / expected - 1.0)) < 1e-9
