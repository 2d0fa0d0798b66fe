"""The memoryless alternative (effects.prerolling = false): Eq. 12 with Karnopp stiction.

Sliding: friction s(v) + sigma2 v.  At rest: the stage is stuck (v = 0 held, x constant)
while |applied force| < F_s, and breaks loose when it reaches F_s.
"""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.physics.friction_curves import steady_friction
from feeddrive.physics.position_maps import cogging
from fmu_loops import FRICTION_ONLY, me_plant, run_at_speed, run_law

pytestmark = pytest.mark.usefixtures("fmu_path")

STATIC = {"effects.prerolling": False}


@pytest.mark.parametrize("direction", [1, -1])
@pytest.mark.parametrize("speed", [0.5e-3, 10e-3, 200e-3])
def test_steady_sliding(paper: dict, speed: float, direction: int) -> None:
    v_ref = direction * speed
    run = run_at_speed(
        dict(FRICTION_ONLY, **STATIC, **{"stroke.x_min": -1.0, "stroke.x_max": 1.0}),
        v_ref,
        paper["m"],
    )
    w = slice(-50, None)
    v = run["v"][w]
    assert np.all(np.abs(v / v_ref - 1.0) < 0.01)
    exp = steady_friction(
        v,
        paper["friction.F_s"],
        paper["friction.F_c"],
        paper["friction.V_s"],
        paper["friction.delta"],
        paper["friction.sigma2"],
    )
    assert np.max(np.abs(run["F_friction"][w] / exp - 1.0)) < 5e-3
    assert np.max(np.abs(-run["F_ext"][w] / exp - 1.0)) < 5e-3
    assert run["n_stuck"][-1] == 0


def _hold(paper: dict, x0: float, F_app: float, T: float = 0.5, cogging_on: bool = True):
    """Static friction, u = 0, F_ext such that -F_cg(x0) - F_ext = F_app; paper model or
    (cogging_on False) friction only."""
    base = {"effects.current_dynamics": False} if cogging_on else FRICTION_ONLY
    F_ext = -(float(cogging(x0, paper)) if cogging_on else 0.0) - F_app
    plant = me_plant(dict(base, **STATIC))
    try:
        return run_law(plant, 1e-3, int(T / 1e-3), None, {"x": x0, "F_ext": F_ext})
    finally:
        plant.close()


@pytest.mark.parametrize("fraction", [0.95, -0.95, 0.5, 0.0])
def test_no_creep_below_static_friction(paper: dict, fraction: float) -> None:
    """|F_app| < F_s from rest: x stays exactly where it was, v = 0, friction balances."""
    x0 = 0.15
    F_app = fraction * paper["friction.F_s"]
    run = _hold(paper, x0, F_app)
    assert np.all(run["x"] == x0)
    assert np.all(run["v"] == 0.0) and np.all(run["a"] == 0.0)
    assert np.all(run["n_stuck"] == 1)
    assert np.allclose(run["F_friction"], F_app, rtol=0, atol=1e-9)
    assert run.state_events == 0


@pytest.mark.parametrize("fraction", [1.02, -1.02])
def test_slides_above_static_friction(paper: dict, fraction: float) -> None:
    """|F_app| = 1.02 F_s: it breaks loose at once and runs away in the push direction
    (friction drops toward F_c = 0.83 F_s).  Friction-only plant: with cogging the applied
    force would change along the way (|dF_cg/dx| up to 16 N/mm)."""
    x0 = 0.15
    run = _hold(paper, x0, fraction * paper["friction.F_s"], T=0.3, cogging_on=False)
    assert run["n_stuck"][0] == 0
    assert np.sign(fraction) * (run["x"][-1] - x0) > 1e-3
    assert run.stats["stats.n_stick"] == 0


def test_breaks_loose_exactly_at_static_friction(paper: dict) -> None:
    """Karnopp: a force ramp (held per 1 ms sample) from 0.9 F_s at 20 N/s leaves the stage
    exactly in place up to the first sample with F_app >= F_s and moves it from then on."""
    Fs, dt, x0 = paper["friction.F_s"], 1e-3, 0.0

    def F_app(t: float) -> float:
        return 0.9 * Fs + 20.0 * t

    plant = me_plant(dict(FRICTION_ONLY, **STATIC))
    try:
        run = run_law(
            plant, dt, 250, lambda k, t, y: (0.0, -F_app(t)), {"x": x0, "F_ext": -F_app(0.0)}
        )
    finally:
        plant.close()
    kb = int(np.argmax(-run["F_ext"] >= Fs))  # first sample pushing with F_s or more
    assert 0 < kb < 240
    assert np.all(run["x"][: kb + 1] == x0) and np.all(run["v"][: kb + 1] == 0.0)
    assert np.all(run["x"][kb + 1 :] > x0)
    assert run["n_stuck"][kb] == 1 and run["n_stuck"][kb + 1] == 0
    assert run.stats["stats.n_slip"] == 1 and run.stats["stats.n_stick"] == 0
