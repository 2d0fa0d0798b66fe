"""Cogging F_cg(x) and force constant K_f(x) (Eqs. 6-7) as the FMU evaluates them."""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.physics.position_maps import cogging, force_constant
from fmu_loops import me_plant, run_law

pytestmark = pytest.mark.usefixtures("fmu_path")

# MODEL.md check values (every harmonic has cos = 1, sin = 0 at these x)
CHECK = [(0.0, 13.97, 67.75), (0.150, 17.5325, 68.30575), (0.300, 24.47, 67.273)]


def _maps_at(x: float, params: dict | None = None) -> tuple[float, float, list[str]]:
    plant = me_plant(params)
    try:
        plant.start({"x": x})
        g = plant.get(["F_cogging", "K_f"])
        return g["F_cogging"], g["K_f"], list(plant.messages)
    finally:
        plant.close()


@pytest.mark.parametrize("x, F_cg, K_f", CHECK)
def test_check_values(x: float, F_cg: float, K_f: float) -> None:
    f, k, msgs = _maps_at(x)
    assert f == pytest.approx(F_cg, abs=1e-6)
    assert k == pytest.approx(K_f, abs=1e-6)
    assert not any("stroke" in m for m in msgs)


def test_maps_match_python_evaluation_inside_stroke(paper: dict) -> None:
    """At arbitrary positions the FMU's maps equal feeddrive.physics.position_maps (1e-9)."""
    for x in (0.0123, 0.0877, 0.2049, 0.2991):
        f, k, _ = _maps_at(x)
        assert f == pytest.approx(float(cogging(x, paper)), abs=1e-9)
        assert k == pytest.approx(float(force_constant(x, paper)), abs=1e-9)


@pytest.mark.parametrize("periodic, aperiodic", [(False, True), (True, False), (False, False)])
def test_effect_switches(paper: dict, periodic: bool, aperiodic: bool) -> None:
    """cogging_/ripple_ periodic and aperiodic off drop the Fourier / polynomial part (K_f keeps c0)."""
    x = 0.2049
    f, k, _ = _maps_at(
        x,
        {
            "effects.cogging_periodic": periodic,
            "effects.cogging_aperiodic": aperiodic,
            "effects.ripple_periodic": periodic,
            "effects.ripple_aperiodic": aperiodic,
        },
    )
    assert f == pytest.approx(
        float(cogging(x, paper, periodic=periodic, aperiodic=aperiodic)), abs=1e-9
    )
    assert k == pytest.approx(
        float(force_constant(x, paper, periodic=periodic, aperiodic=aperiodic)), abs=1e-9
    )
    if not periodic and not aperiodic:
        assert f == 0.0 and k == paper["ripple.c[0]"]


@pytest.mark.parametrize("x, end", [(-0.01, 0), (-1.0, 0), (0.31, 2), (2.0, 2)])
def test_outside_stroke_clamped_and_warned(x: float, end: int) -> None:
    """Outside [0, 0.3] m the maps take their value at the nearest end; a warning names x."""
    f, k, msgs = _maps_at(x)
    assert f == pytest.approx(CHECK[end][1], abs=1e-6)
    assert k == pytest.approx(CHECK[end][2], abs=1e-6)
    warn = [m for m in msgs if "left the stroke" in m]
    assert len(warn) == 1, msgs
    assert f"{x:.9g}" in warn[0]


def test_leaving_the_stroke_in_motion_warns_once(paper: dict) -> None:
    """A stage coasting out of the stroke (ME, CVode) logs one warning; the maps stay clamped."""
    plant = me_plant({"effects.current_dynamics": False})
    try:
        # 0.5 m/s toward +x from 0.2995 m: out after 1 ms; friction + cogging (~47 N on
        # 16.1 kg) slow it by ~3 m/s^2 only, so it keeps going for the 20 ms run
        run = run_law(plant, 1e-3, 20, None, {"x": 0.2995, "v": 0.5})
        msgs = list(plant.messages)
    finally:
        plant.close()
    assert run["x"][-1] > 0.305
    out = run["x"] > 0.3
    assert np.all(np.abs(run["F_cogging"][out] - 24.47) < 1e-6)
    assert np.all(np.abs(run["K_f"][out] - 67.273) < 1e-6)
    assert len([m for m in msgs if "left the stroke" in m]) == 1, msgs
