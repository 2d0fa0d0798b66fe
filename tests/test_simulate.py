"""The Python plant API turns the FMU's rejections into exceptions that name the culprit."""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.fmu import FMUError, Plant
from feeddrive.harness.simulate import simulate_open_loop


def test_nan_input_raises_naming_the_input(fmu_path):
    t = np.arange(20) * 5e-4
    u = np.zeros(20)
    u[5] = np.nan
    with (
        Plant(path=fmu_path) as p,
        pytest.raises(FMUError, match=r"u = nan is not a finite number"),
    ):
        simulate_open_loop(p, t, u)


def test_unknown_parameter_is_named(fmu_path):
    with pytest.raises(KeyError, match=r"friction\.Fs"):
        Plant({"friction.Fs": 1.0}, path=fmu_path)


def test_out_of_range_parameter_is_named_with_its_range(fmu_path):
    with (
        Plant({"m": -2.0}, path=fmu_path) as p,
        pytest.raises(FMUError, match=r"m = -2 is out of range: allowed \(0, inf\) kg"),
    ):
        p.start()


def test_open_loop_current_is_eq2_at_its_samples(fmu_path):
    """Row k holds i[k]: a 1 V step at sample 4 shows b2 = 0.057909 A at sample 6."""
    t = np.arange(12) * 5e-4
    u = np.where(np.arange(12) >= 4, 1.0, 0.0)
    with Plant(
        {"effects.cogging_periodic": False, "effects.cogging_aperiodic": False}, path=fmu_path
    ) as p:
        r = simulate_open_loop(p, t, u)
    assert np.all(r["i"][:6] == 0.0)
    assert r["i"][6] == pytest.approx(0.057909, abs=1e-12)
    assert np.allclose(r["F_motor"], r["K_f"] * r["i"], rtol=0, atol=1e-12)
