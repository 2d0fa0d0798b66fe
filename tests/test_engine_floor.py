"""The engines' floor: libcosim and Ecos stepping a trivial pair of controller FMUs
(feeddrive.systems.floor, the `make bench` rows beside the closed loop at h = Ts).  The pair
is a loop of two gains: each instance's u = -Kp x_meas / force_per_volt of the other's u, so
the outputs stay near 0 (loop gain (Kp/fpv)^2 < 1)."""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.control.pid import DEFAULT_FORCE_PER_VOLT
from feeddrive.systems.floor import (
    pair_values,
    time_ecos_pair,
    time_libcosim_pair,
    time_libcosim_pair_ssp,
    write_pair_osp,
)


def test_pair_structure(ctrl_fmu_path, tmp_path) -> None:
    """Two instances, each one's u into the other's x_meas, h = Ts, a gain only."""
    v = pair_values()
    assert v["ctrl.type"] == 2 and v["pid.Kv"] == 0.0 and v["pid.Ki"] == 0.0
    assert abs(v["pid.Kp"] / DEFAULT_FORCE_PER_VOLT) < 1.0
    text = write_pair_osp(tmp_path).read_text()
    assert text.count("<Simulator ") == 2 and text.count("<VariableConnection>") == 2


def test_engines_step_the_pair(ctrl_fmu_path, tmp_path) -> None:
    pytest.importorskip("libcosimpy", reason="libcosimpy: python/pyproject.toml [test]")
    w = time_libcosim_pair(tmp_path, 200)
    assert np.isfinite(w) and w > 0
    w0 = time_libcosim_pair_ssp(tmp_path, 200)
    assert np.isfinite(w0) and w0 > 0
    try:
        w_e = time_ecos_pair(200)
    except ImportError as e:
        pytest.skip(str(e))
    assert np.isfinite(w_e) and w_e > 0


@pytest.fixture
def ctrl_fmu_path(fmu_path):
    from feeddrive.harness.controller_fmu import controller_fmu_path

    p = controller_fmu_path()
    assert p.is_file()
    return p
