"""Current loop (MODEL.md Eq. 2) through model exchange: exact difference equation at the samples."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from feeddrive.harness.simulate import simulate_open_loop
from feeddrive.physics.position_maps import cogging, force_constant
from fmu_loops import me_plant

pytestmark = pytest.mark.usefixtures("fmu_path")

TS = 5e-4
X0 = 0.15
# Eq. 2 as printed: G(z) = 0.057909 (z + 0.7461) / (z (z^2 - 1.404 z + 0.4938))
B_EQ2 = np.array([0.0, 0.0, 0.057909, 0.057909 * 0.7461])
A_EQ2 = np.array([1.0, -1.404, 0.4938])


def _u_step(n: int) -> np.ndarray:
    """u = 0 at t_0, then a step to 0.2 V with a small PRBS-like ripple (so every tap counts)."""
    rng = np.random.default_rng(7)
    u = 0.2 + 0.05 * rng.choice([-1.0, 1.0], size=n)
    u[0] = 0.0
    return u


def test_eq2_coefficients_and_dc_gain(paper: dict) -> None:
    a = [paper[f"current.a[{j}]"] for j in range(1, 6)]
    b = [paper[f"current.b[{j}]"] for j in range(6)]
    assert np.allclose(b[:4], B_EQ2, rtol=0, atol=5e-7)  # 0.057909 * 0.7461 = 0.0432059
    assert np.allclose([1.0] + [-x for x in a[:2]], A_EQ2, rtol=0, atol=1e-15)
    assert sum(b) / (1.0 - sum(a)) == pytest.approx(1.1260, abs=5e-5)


def test_current_equals_difference_equation_at_samples(paper: dict) -> None:
    """i at the sample instants is lfilter(Eq. 2) of the same u samples to 1e-9 A.

    Convention (feeddrive.harness.simulate): u[k] is set at t_k before the FMU's sample at t_k, and
    the recorded row k holds i[k], the current held over [t_k, t_{k+1}).  F_ext balances
    K_f(x0) i - F_cg(x0), so the stage stays put (i does not depend on motion anyway)."""
    n = 400
    u = _u_step(n)
    b = np.array([paper[f"current.b[{j}]"] for j in range(6)])
    a = np.concatenate([[1.0], [-paper[f"current.a[{j}]"] for j in range(1, 6)]])
    i_ref = lfilter(b, a, u)
    F_ext = float(force_constant(X0, paper)) * i_ref - float(cogging(X0, paper))
    t = np.arange(n + 1) * TS
    plant = me_plant({}, tolerance=1e-8)
    try:
        res = simulate_open_loop(
            plant, t, np.append(u, u[-1]), np.append(F_ext, F_ext[-1]), start_values={"x": X0}
        )
    finally:
        plant.close()
    assert np.max(np.abs(res["i"][:n] - i_ref)) < 1e-9
    # independently of the FMU parameters: the printed Eq. 2 gives the same currents (5e-7
    # rounding of b3 = 0.057909 * 0.7461 on |u| <= 0.25 V, gain ~1.1: < 1e-5 A)
    assert np.max(np.abs(res["i"][:n] - lfilter(B_EQ2, A_EQ2, u))) < 1e-5
    # the stage did not move (force balanced): < 1 um
    assert np.max(np.abs(res["x"] - X0)) < 1e-6


def test_step_settles_at_dc_gain() -> None:
    """A 0.1 V step settles at G(1) u = 0.11260 A (poles |z| = 0.70: 0.7^150 ~ 1e-23)."""
    n = 200
    u = np.full(n + 1, 0.1)
    u[0] = 0.0
    t = np.arange(n + 1) * TS
    plant = me_plant({"effects.cogging_periodic": False, "effects.cogging_aperiodic": False})
    try:
        res = simulate_open_loop(plant, t, u, -70.0 * 0.1126, start_values={"x": X0})
    finally:
        plant.close()
    i = res["i"]
    # row k is i[k] = 0.057909 u[k-2] + ...: zero up to i[2], then the b2 tap
    assert np.all(i[:3] == 0.0)
    assert i[3] == pytest.approx(0.1 * 0.057909, abs=1e-12)
    assert np.max(np.abs(i[150:] - 1.1260 * 0.1)) < 1e-5
    assert np.max(np.abs(i[150:] - i[-1])) < 1e-12


def test_current_dynamics_off_is_dc_gain_instantly(paper: dict) -> None:
    """effects.current_dynamics = false: i = G(1) u at once, at any time."""
    g1 = sum(paper[f"current.b[{j}]"] for j in range(6)) / (
        1.0 - sum(paper[f"current.a[{j}]"] for j in range(1, 6))
    )
    n = 50
    u = _u_step(n + 1)
    u[0] = 0.3
    t = np.arange(n + 1) * 1e-3  # no samples to keep: any grid
    plant = me_plant({"effects.current_dynamics": False})
    try:
        F_ext = float(force_constant(X0, paper)) * g1 * u - float(cogging(X0, paper))
        res = simulate_open_loop(plant, t, u, F_ext, start_values={"x": X0})
        i0 = plant.get(["i"])["i"]
    finally:
        plant.close()
    assert g1 == pytest.approx(1.1260, abs=5e-5)
    assert res["i"][0] == pytest.approx(g1 * u[0], rel=1e-12)
    assert np.max(np.abs(res["i"][:-1] - g1 * u[:-1])) < 1e-12
    assert i0 == pytest.approx(g1 * u[-2], rel=1e-12)
