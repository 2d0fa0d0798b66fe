"""Steady sliding friction (Eq. 12): F_f = s(v) + sigma2 v once the GMS elements have settled.

The stage is held at constant speed by a velocity loop around the FMU (model exchange,
CVode) acting through F_ext on a friction-only plant (u = 0, no cogging or ripple).  At
constant speed F_ext = -(friction acting on the stage), so both the F_friction output
and the force the loop must apply are compared with s(v) + sigma2 v at the measured v.
"""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.physics.friction_curves import steady_friction
from fmu_loops import FRICTION_ONLY, VelocityLoop, me_plant, run_law

pytestmark = pytest.mark.usefixtures("fmu_path")

SPEEDS = [0.5e-3, 1e-3, 3e-3, 10e-3, 50e-3, 200e-3]  # m/s
RAMP = 0.02  # s, 0 -> v_ref
DT_SLOW = 5e-3  # s, loop sample for C = 10.8


def _expected(v: np.ndarray, p: dict) -> np.ndarray:
    return steady_friction(
        v,
        p["friction.F_s"],
        p["friction.F_c"],
        p["friction.V_s"],
        p["friction.delta"],
        p["friction.sigma2"],
    )


def _slide(p: dict, v_ref: float, C: float, dt: float, T: float) -> dict:
    params = dict(FRICTION_ONLY, **{"friction.C": C, "stroke.x_min": -3.0, "stroke.x_max": 3.0})
    plant = me_plant(params)
    try:
        law = VelocityLoop(lambda t: v_ref * min(t / RAMP, 1.0), p["m"], dt)
        run = run_law(plant, dt, int(round(T / dt)), law, {"x": 0.0})
    finally:
        plant.close()
    return {"run": run, "messages": list(plant.messages)}


def _check(out: dict, p: dict, v_ref: float, window: float, dt: float) -> None:
    run = out["run"]
    w = slice(-int(round(window / dt)), None)
    v = run["v"][w]
    exp = _expected(v, p)
    assert np.all(np.abs(v / v_ref - 1.0) < 0.01), "the loop did not hold the speed"
    # the output: sum of element forces + sigma2 v
    assert np.max(np.abs(run["F_friction"][w] / exp - 1.0)) < 5e-3
    # the force that really acts: what the loop applies at constant speed
    assert np.max(np.abs(-run["F_ext"][w] / exp - 1.0)) < 5e-3
    assert run.stats["stats.n_slip"] == 5 and run["n_stuck"][-1] == 0
    assert not out["messages"], out["messages"]


@pytest.mark.parametrize("direction", [1, -1])
@pytest.mark.parametrize("speed", SPEEDS)
def test_steady_sliding_fast_attraction(paper: dict, speed: float, direction: int) -> None:
    """C = 1.08e4 N/s (MODEL.md default): slip relaxation S/C ~ 2.4 ms; 0.6 s from rest."""
    v_ref = direction * speed
    _check(_slide(paper, v_ref, 1.08e4, 2e-3, 0.6), paper, v_ref, 0.1, 2e-3)


@pytest.mark.parametrize("direction", [1, -1])
@pytest.mark.parametrize("speed", SPEEDS)
def test_steady_sliding_literal_attraction(paper: dict, speed: float, direction: int) -> None:
    """C = 10.8 N/s (the paper's literal number): slip relaxation S/C ~ 2.0-2.4 s.

    From rest, each element breaks away during the 20 ms speed ramp at nu_i S(|v_b|), v_b
    its break-away speed, and then relaxes toward nu_i S(v_ref) with time constant S/C
    (test_fmu_frictional_lag checks that law).  The sum starts up to ~3 % above
    s(v_ref) + sigma2 v_ref (at 10 mm/s) and needs ln(3 / 0.5) = 1.8 time constants to come
    within 0.5 %: the 8 s run gives 3.5.  The stroke is widened to [-3, 3] m: the maps are
    off, 200 mm/s * 8 s = 1.6 m."""
    v_ref = direction * speed
    _check(_slide(paper, v_ref, 10.8, DT_SLOW, 8.0), paper, v_ref, 0.2, DT_SLOW)
