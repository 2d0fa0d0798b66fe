"""N = 1..10 GMS elements: a plant with one element and one with all ten slots in use."""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.physics.friction_curves import steady_friction
from fmu_loops import FRICTION_ONLY, PositionLoop, me_plant, run_at_speed, run_law, triangle

pytestmark = pytest.mark.usefixtures("fmu_path")

K10 = [1152.07e3, 377.23e3, 215.33e3, 9.39e3, 87.66e3, 5e5, 2e5, 5e4, 2e4, 1e4]  # N/m


def _params(N: int) -> dict:
    p = dict(FRICTION_ONLY, **{"friction.N": N, "stroke.x_min": -1.0, "stroke.x_max": 1.0})
    for j in range(1, N + 1):
        p[f"friction.nu[{j}]"] = 1.0 / N
        p[f"friction.k[{j}]"] = K10[j - 1] if N > 1 else 1e6
    return p


def _freq(t: np.ndarray, x: np.ndarray) -> float:
    d = x - x.mean()
    i = np.nonzero((d[:-1] < 0) & (d[1:] >= 0))[0]
    tc = t[i] - d[i] * (t[i + 1] - t[i]) / (d[i + 1] - d[i])
    return (len(tc) - 1) / (tc[-1] - tc[0])


@pytest.mark.parametrize("N", [1, 10])
def test_ringing_uses_all_N_springs(paper: dict, N: int) -> None:
    """At rest every element is stuck; a small kick rings at sqrt(sum_{i<=N} k_i / m)."""
    params = _params(N)
    plant = me_plant(params)
    try:
        run = run_law(plant, 5e-4, 600, None, {"x": 0.0, "v": 1e-5})
    finally:
        plant.close()
    assert np.all(run["n_stuck"] == N)
    assert run.state_events == 0
    ksum = sum(params[f"friction.k[{j}]"] for j in range(1, N + 1))
    assert _freq(run["time"], run["x"]) == pytest.approx(
        np.sqrt(ksum / paper["m"]) / (2 * np.pi), rel=1e-3
    )


@pytest.mark.parametrize("direction", [1, -1])
@pytest.mark.parametrize("N", [1, 10])
def test_steady_sliding_with_N_elements(paper: dict, N: int, direction: int) -> None:
    """Sum nu = 1 with any N: steady sliding at 10 mm/s is s(v) + sigma2 v (0.5 %)."""
    run = run_at_speed(_params(N), direction * 10e-3, paper["m"])
    w = slice(-50, None)
    exp = steady_friction(
        run["v"][w],
        paper["friction.F_s"],
        paper["friction.F_c"],
        paper["friction.V_s"],
        paper["friction.delta"],
        paper["friction.sigma2"],
    )
    assert np.max(np.abs(run["F_friction"][w] / exp - 1.0)) < 5e-3
    assert np.max(np.abs(-run["F_ext"][w] / exp - 1.0)) < 5e-3
    assert run.stats["stats.n_slip"] == N and run["n_stuck"][-1] == 0


def test_virgin_curve_with_ten_elements(paper: dict) -> None:
    """Pre-rolling from rest with N = 10: F = sum_i min(k_i d, nu_i F_s) to 2 % of F_s
    (at 5e-5 m/s, S(|v|) = 0.986 F_s)."""
    params = _params(10)
    ref, knots = triangle([0.0, 60e-6], 5e-5, t_hold=0.02)
    plant = me_plant(params)
    try:
        run = run_law(plant, 4e-3, int(knots[-1] / 4e-3), PositionLoop(ref, paper["m"]), {"x": 0.0})
    finally:
        plant.close()
    k = np.array(K10)
    L = 0.1 * paper["friction.F_s"] * np.ones(10)
    d = run["x"]
    expected = np.minimum(np.outer(np.abs(d), k), L).sum(axis=1) * np.sign(d)
    assert np.max(np.abs(run["F_friction"] - expected)) < 0.02 * paper["friction.F_s"]
    # 60 um is past Delta_i = nu_i F_s / k_i of elements 1-3 and 5-8 (2.3..52 um); elements
    # 4, 9, 10 (Delta = 278, 130, 261 um) are still stuck
    assert run["n_stuck"][-1] == 3
