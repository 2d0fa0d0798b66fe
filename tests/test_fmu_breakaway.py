"""Break-away: a slow force ramp on a stage at rest starts gross sliding when the applied
force (motor, cogging and external) reaches the static friction F_s.

Paper model (cogging on), u = 0, model exchange with CVode.  F_ext starts at -F_cg(x0)
(cogging balanced: applied force 0) and ramps at 10 N/s, with a dash-pot of 2000 N s/m in
the load (F_ext += c v): without it the lightly damped pre-sliding modes (zeta ~ 0.5 %
from sigma2 alone) ring and break the elements loose early.  Gross sliding is the first
sample with every element slipping (n_stuck = 0).  There the applied force
    F_app = K_f i - F_cg(x_b) - F_ext = -F_cg(x_b) - F_ext
must be F_s in size: the elements slip at nu_i S(|v|), and the pre-sliding speed
r / k_5 ~ 1.1e-4 m/s gives S = 0.979 F_s, so the tolerance is 3 % of F_s.  Sharper, it
must equal S(|v_b|) + sigma2 |v_b| + m a_b (the motion equation at that sample) to 0.5 %.
"""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.physics.friction_curves import stribeck_level
from feeddrive.physics.position_maps import cogging
from fmu_loops import me_plant, run_law

pytestmark = pytest.mark.usefixtures("fmu_path")

RATE, DAMPER, DT = 10.0, 2000.0, 4e-3


@pytest.mark.parametrize("direction", [1, -1])
@pytest.mark.parametrize("x0", [0.15, 0.10])
def test_breakaway_at_static_friction_plus_cogging(paper: dict, x0: float, direction: int) -> None:
    Fs = paper["friction.F_s"]
    F_cg0 = float(cogging(x0, paper))

    def law(k: int, t: float, y: dict) -> tuple[float, float]:
        return 0.0, -F_cg0 - direction * RATE * t + DAMPER * y["v"]

    plant = me_plant({"effects.current_dynamics": False}, tolerance=1e-6)
    try:
        run = run_law(
            plant,
            DT,
            int(1.3 * Fs / RATE / DT),
            law,
            {"x": x0, "F_ext": -F_cg0},
            stop=lambda k, y: y["n_stuck"] == 0,
        )
    finally:
        plant.close()
    n = run["n_stuck"]
    assert n[0] == 5 and n[-1] == 0, "no gross sliding within the ramp"
    kb = len(n) - 1
    xb, vb = run["x"][kb], run["v"][kb]
    # pre-sliding travel is Delta_5 = nu_5 F_s / k_5 = 113 um (virgin curve), in the push direction
    assert 0.8 * 113e-6 < direction * (xb - x0) < 1.1 * 113e-6
    F_app = -float(cogging(xb, paper)) - run["F_ext"][kb - 1]  # held over the last sample
    assert np.sign(F_app) == direction
    assert abs(abs(F_app) - Fs) < 0.03 * Fs
    S = float(
        stribeck_level(
            vb, Fs, paper["friction.F_c"], paper["friction.V_s"], paper["friction.delta"]
        )
    )
    dyn = direction * (S + paper["friction.sigma2"] * abs(vb)) + paper["m"] * run["a"][kb]
    assert abs(F_app - dyn) < 0.005 * Fs
    # the cogging shifts the external force at break-away: F_ext = -F_cg(x0) - F_s sgn, to
    # 3 % of F_s plus what F_cg can change over the 0.11 mm travel (|dF_cg/dx| < 16 N/mm)
    assert run["F_ext"][kb - 1] == pytest.approx(-F_cg0 - direction * Fs, abs=0.03 * Fs + 2.0)
    # every element slipped once, none re-stuck on the way (the dash-pot keeps v > 0)
    assert run.stats["stats.n_slip"] == 5 and run.stats["stats.n_stick"] == 0
