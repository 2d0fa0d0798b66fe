"""Pre-rolling (MODEL.md, Maxwell-slip limit Eq. 15): hysteresis curves and non-local memory.

The position is moved slowly (5e-5 m/s) inside the pre-rolling range by a stiff position
loop around the FMU (model exchange, CVode; friction-only plant, F_ext drives it):
x0 -> x0+A -> x0-A -> x0+B -> x0+B-b (inner loop) -> x0+B -> x0+A with A = 60 um (past
Delta_1..Delta_4 = 3.9..47 um, short of Delta_5 = 113 um), B = 20 um, b = 30 um.

Expected curves: element i is a spring k_i clipped at +-L_i.  The paper's Maxwell-slip form
uses L_i = nu_i F_s; the GMS elements slip at nu_i S(|v|), and at 5e-5 m/s
S = 25.74 N = 0.986 F_s.  Tolerances: 2 % of F_s against the F_s-level curves (the 1.4 %
Stribeck drop plus tracking), 0.5 % of F_s against the S(|v|)-level curve.
"""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.physics.friction_curves import stribeck_level
from fmu_loops import FRICTION_ONLY, PositionLoop, maxwell_slip, me_plant, run_law, triangle

pytestmark = pytest.mark.usefixtures("fmu_path")

X0, A, B, b = 0.15, 60e-6, 20e-6, 30e-6
SPEED, DT = 5e-5, 4e-3


@pytest.fixture(scope="module")
def loop(paper: dict, fmu_path) -> dict:  # fmu_path: on the module's FMI version
    path = [X0, X0 + A, X0 - A, X0 + B, X0 + B - b, X0 + B, X0 + A]
    ref, knots = triangle(path, SPEED, t_hold=0.05)
    plant = me_plant(FRICTION_ONLY)
    try:
        run = run_law(plant, DT, int(knots[-1] / DT) + 25, PositionLoop(ref, paper["m"]), {"x": X0})
    finally:
        plant.close()
    k = np.array([paper[f"friction.k[{j}]"] for j in range(1, 6)])
    nu = np.array([paper[f"friction.nu[{j}]"] for j in range(1, 6)])
    S = float(
        stribeck_level(
            SPEED,
            paper["friction.F_s"],
            paper["friction.F_c"],
            paper["friction.V_s"],
            paper["friction.delta"],
        )
    )
    return {
        "run": run,
        "knots": knots,
        "k": k,
        "L_Fs": nu * paper["friction.F_s"],
        "L_S": nu * S,
        "F_s": paper["friction.F_s"],
    }


def _leg(loop: dict, j: int) -> tuple[np.ndarray, np.ndarray]:
    """Displacement and friction on leg j (from point j to j+1), ends trimmed by 2 samples."""
    t = loop["run"]["time"]
    m = (t > loop["knots"][j] + 2 * DT) & (t < loop["knots"][j + 1] - 2 * DT)
    return loop["run"]["x"][m] - X0, loop["run"]["F_friction"][m]


def test_position_followed(loop: dict) -> None:
    d, _ = _leg(loop, 0)
    assert d.min() > -1e-6 and abs(loop["run"]["x"].max() - (X0 + A)) < 1e-6


def test_whole_path_equals_maxwell_slip(loop: dict) -> None:
    """Along the whole path the FMU's friction equals the Maxwell-slip model driven by the
    same displacement samples."""
    run = loop["run"]
    d = run["x"] - X0
    err_S = np.max(np.abs(run["F_friction"] - maxwell_slip(d, loop["k"], loop["L_S"])))
    err_Fs = np.max(np.abs(run["F_friction"] - maxwell_slip(d, loop["k"], loop["L_Fs"])))
    assert err_S < 0.005 * loop["F_s"]
    assert err_Fs < 0.02 * loop["F_s"]


def test_virgin_curve(loop: dict) -> None:
    """From rest: F = sum_i min(k_i d, nu_i F_s)."""
    d, F = _leg(loop, 0)
    expected = np.minimum(np.outer(d, loop["k"]), loop["L_Fs"]).sum(axis=1)
    assert np.max(np.abs(F - expected)) < 0.02 * loop["F_s"]
    assert F[-1] > 0.5 * loop["F_s"]  # the curve went well into pre-rolling


def test_branch_after_reversal(loop: dict) -> None:
    """After the reversal at d = A: F_i = max(min(k_i A, L_i) - k_i (A - d), -L_i)."""
    d, F = _leg(loop, 1)
    FA = np.minimum(loop["k"] * A, loop["L_Fs"])
    expected = np.maximum(FA - np.outer(A - d, loop["k"]), -loop["L_Fs"]).sum(axis=1)
    assert np.max(np.abs(F - expected)) < 0.02 * loop["F_s"]
    assert F[0] > 0 > F[-1]  # the force reverses within the range


def test_inner_loop_closes_on_outer_loop(loop: dict) -> None:
    """Non-local memory: after the inner loop B -> B-b -> B the force at B is the force the
    outer ascending branch had at B, and the rest of the leg follows the outer branch."""
    run = loop["run"]
    t = run["time"]

    def F_at(tk: float) -> float:
        return float(np.interp(tk, t, run["F_friction"]))

    F_before = F_at(loop["knots"][3])  # at x0+B, moving up, before the inner loop
    F_after = F_at(loop["knots"][5])  # at x0+B again, after it
    assert abs(F_after - F_before) < 0.02 * loop["F_s"]
    # the inner loop is a real excursion: the force at its bottom is far from F_before
    assert abs(F_at(loop["knots"][4]) - F_before) > 0.2 * loop["F_s"]
    # outer ascending branch from the reversal at -A (element forces F_i(-A)), no inner loop
    d, F = _leg(loop, 5)
    F_i_mA = np.clip(
        np.minimum(loop["k"] * A, loop["L_Fs"]) - loop["k"] * 2 * A, -loop["L_Fs"], loop["L_Fs"]
    )
    outer = np.clip(F_i_mA + np.outer(d + A, loop["k"]), -loop["L_Fs"], loop["L_Fs"]).sum(axis=1)
    assert np.max(np.abs(F - outer)) < 0.02 * loop["F_s"]


def test_maxwell_slip_helper_closed_forms() -> None:
    """The reference model of these tests against hand-derived values (two elements)."""
    k, L = np.array([1e6, 1e5]), np.array([2.0, 3.0])  # Delta = 2 um, 30 um
    path = np.array([0.0, 1e-6, 10e-6, 40e-6, 35e-6, 0.0, -40e-6])
    F = maxwell_slip(path, k, L)
    assert F == pytest.approx(
        [0.0, 1.0 + 0.1, 2.0 + 1.0, 2.0 + 3.0, -2.0 + 2.5, -2.0 - 1.0, -2.0 - 3.0], abs=1e-12
    )
