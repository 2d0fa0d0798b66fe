"""Plant(parameters={"solver.tol": ...}) sets the co-simulation integrator's tolerance (the
experiment tolerance of fmi2SetupExperiment would otherwise override the parameter)."""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.fmu import Plant
from feeddrive.harness.simulate import simulate_open_loop

pytestmark = pytest.mark.usefixtures("fmu_path")  # on both FMI versions (conftest)


def _x(parameters: dict, tolerance: float = 1e-6) -> np.ndarray:
    t = np.arange(400) * 5e-4
    u = 0.4 * np.sign(np.sin(2 * np.pi * 5 * t))  # reversals: friction switches
    with Plant(parameters, interface="cs", tolerance=tolerance) as plant:
        return np.asarray(simulate_open_loop(plant, t, u, start_values={"x": 0.15})["x"])


def test_solver_tol_parameter_takes_effect(fmu_path):
    loose = _x({"solver.tol": 1e-2})
    tight = _x({"solver.tol": 1e-10})
    assert np.max(np.abs(loose - tight)) > 1e-9  # the loose run is visibly different
    np.testing.assert_array_equal(loose, _x({}, tolerance=1e-2))  # same as the argument
    np.testing.assert_array_equal(tight, _x({}, tolerance=1e-10))
