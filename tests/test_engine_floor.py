"""The engines' floor: libcosim and Ecos stepping a trivial pair of controller FMUs
(feeddrive.systems.floor, the `make bench` rows beside the closed loop at h = Ts).  The pair
is a loop of two gains: each instance's u = -Kp x_meas / force_per_volt of the other's u, so
the outputs stay near 0 (loop gain (Kp/fpv)^2 < 1)."""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest

from feeddrive.control.pid import DEFAULT_FORCE_PER_VOLT
from feeddrive.systems.floor import (
    pair_values,
    time_container_pair,
    time_ecos_pair,
    time_libcosim_pair,
    time_libcosim_pair_ssp,
    write_pair_container,
    write_pair_osp,
)


def test_pair_structure(ctrl_fmu_path, tmp_path) -> None:
    """Two instances, each one's u into the other's x_meas, h = Ts, a gain only."""
    v = pair_values()
    assert v["ctrl.type"] == 2 and v["pid.Kv"] == 0.0 and v["pid.Ki"] == 0.0
    assert abs(v["pid.Kp"] / DEFAULT_FORCE_PER_VOLT) < 1.0
    text = write_pair_osp(tmp_path).read_text()
    assert text.count("<Simulator ") == 2 and text.count("<VariableConnection>") == 2


def test_pair_container(ctrl_fmu_path, tmp_path) -> None:
    """The pair as fmpy's container FMU: two components, two connections, the outputs a_u,
    b_u, the pair's start values as its parameters; simulate_fmu steps it at Ts."""
    from fmpy import read_model_description, simulate_fmu

    fmu = write_pair_container(tmp_path / "pair.fmu", n=200)
    md = read_model_description(str(fmu))
    names = {v.name for v in md.modelVariables}
    assert {"a_u", "b_u", "a.pid.Kp", "b.pid.Kp"} <= names
    assert float(md.defaultExperiment.stepSize) == 5e-4
    with zipfile.ZipFile(fmu) as z:  # read a byte per call by the container: compact
        conf = z.read("resources/container.json")
        names = z.namelist()
    assert b"\n" not in conf and len(json.loads(conf)["components"]) == 2
    assert "resources/DriveController/binaries/linux64/DriveController.so" in names
    assert not [n for n in names if "/sources/" in n]  # extracted on every simulate_fmu
    r = simulate_fmu(str(fmu), stop_time=0.1, step_size=5e-4, output=["a_u", "b_u"])
    # each u = k (x_ref - x_meas), k = Kp / force_per_volt, x_meas the other's u, x_ref the
    # FMU's default input 0.15 m: the loop gain k^2 < 1 settles both at k x_ref / (1 + k)
    k = pair_values()["pid.Kp"] / pair_values()["pid.force_per_volt"]
    fixed = k * 0.15 / (1.0 + k)
    assert abs(r["a_u"][-1] - fixed) < 1e-9 and abs(r["b_u"][-1] - fixed) < 1e-9
    assert np.isfinite(time_container_pair(tmp_path, 200))


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


def test_engine_row_says_what_stops_the_target() -> None:
    """The bench row: our figure beside the floor; a missed target names the floor when the
    floor alone exceeds it, else what the loop takes beyond the floor."""
    from feeddrive.bench_engines import engine_row

    py, n = 0.042, 12000  # the target is 14 ms
    met = engine_row("e", 0.012, 0.010, py, n)
    assert met[2].endswith(": met") and "ours beyond it 2 ms" in met[1]
    floor = engine_row("e", 0.106, 0.085, py, n)
    assert "the engine's floor alone is 85 ms" in floor[2]
    ours = engine_row("e", 0.030, 0.010, py, n)
    assert "leaves 4 ms to the FMUs, the loop takes 20 ms beyond it" in ours[2]
    below = engine_row("e", 0.080, 0.085, py, n)
    assert "at or below it" in below[1]
    assert engine_row("e", float("nan"), float("nan"), py, n)[1].startswith("not measured")
