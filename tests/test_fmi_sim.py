"""The FMU in the Rust ``fmi-sim`` 0.7.0 (crates.io; tests/fmi_sim.py; installed by ``make
importers``), co-simulation and model exchange, on the importer scenario (tests/importer_scenario.py),
against fmpy's runs of the same input.

Tolerances:
* CS against fmpy CS: the same binary doing the same fmi2DoStep(k Ts, Ts) calls (fmi-sim's t_k
  is t0 + k h as fmpy's); u may differ in its last bit (fmi-sim interpolates its input file
  linearly, u_k-1 + 1.0 (u_k - u_k-1)): 1e-12 m, 1e-8 N as FMI4j's (measured: bitwise equal).
* ME: fmi-sim integrates with forward Euler (its only solver) at a fixed step h, cut at the
  FMU's time events (the 0.5 ms samples); state events (friction switches) are detected after
  the step, not located.  Both errors are first order in h: the deviation from fmpy's ME
  (CVode at 1e-9, its own error ~0.04 um) is C h.  The test runs h = 20 us and 10 us and asks
  (a) the deviation in x to halve with h (ratio 1.6..2.5: the method's order, not a chance
  agreement) and (b) at 10 us, at most 1.5 times Richardson's estimate of the 10 us run's error,
  |y(20 us) - y(10 us)| (for a first-order method equal to it), plus the importers' ME
  tolerance for fmpy's own error, 0.1 um and 0.05 N.  Measured at 10 us: 10.9 um, 0.82 N
  (C = 1.1 m/s: forward Euler through the friction switches; 0.1 um would need h = 0.1 us).
  Compared before the stop time: at t = 2 s fmi-sim also takes the sample, the harness not.

FMI 3.0: :func:`fmi_sim.run_fmi_sim` takes the FMU as a parameter and is not FMI-2 specific;
only the FMI 2.0 FMU is tested here.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fmi_sim import fmi_sim_exe, on_grid, run_fmi_sim
from importer_scenario import COLUMNS, X0, end_of_step_to_sampled, fmpy_runs, grid, max_dev, u_input

EXE, WHY = fmi_sim_exe()
pytestmark = pytest.mark.skipif(EXE is None, reason=WHY)

ME_STEPS = (2e-5, 1e-5)


def run_scenario(
    fmu: Path, interface: str, out_dir: Path, step: float | None = None
) -> dict[str, np.ndarray]:
    """The importer scenario in fmi-sim: outputs on the grid, the current as the harness's i[k]."""
    t = grid()
    run = run_fmi_sim(
        EXE, fmu, interface, t, {"u": u_input(t)}, {"x": X0, "v": 0.0}, out_dir, step=step
    )
    d = on_grid(run, t, COLUMNS)
    if interface == "cs":  # read at the end of each step; ME: recorded after the event at t_k
        d["i"] = end_of_step_to_sampled(d["i"])
    return d


@pytest.fixture(scope="module")
def fmi_sim_runs(fmu_path, tmp_path_factory) -> dict[str, dict[str, np.ndarray]]:
    out = tmp_path_factory.mktemp("fmi_sim")
    runs = {"cs": run_scenario(fmu_path, "cs", out)}
    for h in ME_STEPS:
        runs[f"me{h:g}"] = run_scenario(fmu_path, "me", out / f"h{h:g}", step=h)
    return runs


def test_fmi_sim_ran_the_scenario(fmi_sim_runs) -> None:
    for d in fmi_sim_runs.values():
        assert len(d["x"]) == len(grid())
        assert np.all(np.isfinite(d["x"])) and np.ptp(d["x"]) > 0.03  # tens of millimetres


def test_fmi_sim_cs_equals_fmpy_cs(fmi_sim_runs, fmu_path) -> None:
    dev = max_dev(fmi_sim_runs["cs"], fmpy_runs(fmu_path)["cs"])
    print("fmi-sim CS vs fmpy CS:", dev)
    assert dev["x"] < 1e-12 and dev["F_friction"] < 1e-8 and dev["i"] < 1e-12


def _before_stop(d: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    return {c: v[:-1] for c, v in d.items()}


def test_fmi_sim_me_euler_converges_to_fmpy_me(fmi_sim_runs, fmu_path) -> None:
    ref = _before_stop(fmpy_runs(fmu_path)["me"])
    coarse, fine = (_before_stop(fmi_sim_runs[f"me{h:g}"]) for h in ME_STEPS)
    devs = [max_dev(coarse, ref), max_dev(fine, ref)]
    est = max_dev(coarse, fine)  # Richardson: the fine run's error, first order
    for h, d in zip(ME_STEPS, devs, strict=True):
        print(f"fmi-sim ME (Euler, h = {h:g} s) vs fmpy ME:", d)
    print("Richardson estimate of the fine run's error:", est)
    ratio = devs[0]["x"] / devs[1]["x"]
    assert 1.6 < ratio < 2.5, f"deviation in x not first order in h: ratio {ratio:.2f}"
    assert devs[1]["x"] <= 1.5 * est["x"] + 0.1e-6
    assert devs[1]["F_friction"] <= 1.5 * est["F_friction"] + 0.05
    assert devs[1]["i"] <= 1.5 * est["i"] + 1e-9
