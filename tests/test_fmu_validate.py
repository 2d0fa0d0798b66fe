"""The packaged FMU, FMI 2.0 and FMI 3.0, passes fmpy's validation and runs under fmpy's own
model-exchange driver."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import fmpy
import numpy as np
from fmpy.validation import validate_fmu


def test_fmpy_validate_reports_no_problems(fmu_version: tuple[Path, str]) -> None:
    fmu_path, _ = fmu_version
    problems = validate_fmu(str(fmu_path))
    assert problems == [], "fmpy validation problems:\n" + "\n".join(problems)


def test_fmpy_validate_cli(fmu_version: tuple[Path, str]) -> None:
    fmu_path, _ = fmu_version
    out = subprocess.run(
        [sys.executable, "-m", "fmpy.cli", "validate", str(fmu_path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    assert "No problems found" in out.stdout


def test_model_description_declares_both_interfaces(fmu_version: tuple[Path, str]) -> None:
    fmu_path, version = fmu_version
    md = fmpy.read_model_description(str(fmu_path))
    assert md.fmiVersion == version
    assert md.modelExchange is not None and md.coSimulation is not None
    # FMI 2.0: x, v, friction.F[1..10], compliance.dx, compliance.dv; FMI 3.0: x, v, the array
    # friction.F of dimension friction.N (5 by default), compliance.dx, compliance.dv
    assert md.numberOfContinuousStates == (14 if version == "2.0" else 9)
    assert md.numberOfEventIndicators == 11  # one per element + the motion direction


def test_simulate_fmu_model_exchange_cvode_stage_at_rest(fmu_version: tuple[Path, str]) -> None:
    """fmpy.simulate_fmu (ME, CVode, time events of the 2 kHz current loop) from the default
    start: x = 0.15 m, u = 0.  F_cg(0.15) = 17.53 N < F_s = 26.1 N, so the stage only
    pre-slides: it must stay within 2 Delta_5 = 0.23 mm of the start and come to rest."""
    fmu_path, _ = fmu_version
    res = fmpy.simulate_fmu(
        str(fmu_path),
        fmi_type="ModelExchange",
        solver="CVode",
        stop_time=0.3,
        output_interval=5e-4,
        relative_tolerance=1e-8,
        output=["x", "v", "F_cogging", "F_friction", "n_stuck"],
    )
    for name in ("x", "v", "F_cogging", "F_friction"):
        assert np.all(np.isfinite(res[name])), name
    assert np.max(np.abs(res["x"] - 0.15)) < 0.23e-3
    assert res["n_stuck"][-1] == 5  # all elements stuck again at rest
    assert abs(res["F_cogging"][0] - 17.5325) < 1e-6
