"""Run one system in every engine and compare with the harness's two-FMU run."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..harness.two_fmus import simulate_two_fmus
from .closed_loop import ClosedLoopSystem
from .engines import run_container, run_fmpy_ssp, run_libcosim_osp
from .jacobi import simulate_jacobi


def compare_engines(system: ClosedLoopSystem, files: dict[str, Path]) -> list[str]:
    """One line per engine: max |x - x_harness| (and, for the Jacobi engines, against the
    Jacobi master of the same convention) [um] and the engine's wall time [s]."""
    h = simulate_two_fmus(system.plant, system.controller, system.n, system.x0)
    j = simulate_jacobi(system)
    N = system.jacobi_substeps

    def gap(r, ref) -> float:
        return float(np.nanmax(np.abs(r["x"][1:] - ref["x"][1:]))) * 1e6

    lines = [
        f"{system.name}: {system.n} samples of Ts = {system.Ts * 1e3:g} ms; harness: macro "
        f"step Ts, computation delay {system.delay} sample(s); Jacobi engines: macro step "
        f"Ts/{N}, one step late, ctrl.delay {system.ctrl_delay(jacobi=True)}"
    ]
    runs = [
        (
            "fmpy container FMU (simulate_fmu)",
            run_container(files["container"], system.n, system.Ts),
            False,
        ),
        (
            "libcosim (OspSystemStructure.xml)",
            run_libcosim_osp(files["osp"].parent, system.n, system.Ts, N),
            True,
        ),
        ("fmpy simulate_ssp (.ssp)", run_fmpy_ssp(files["ssp"], system.n, system.Ts, N), True),
    ]
    for name, r, jacobi in runs:
        extra = f", vs the Jacobi master {gap(r, j):.4g} um" if jacobi else ""
        lines.append(
            f"  {name:36s} vs harness {gap(r, h):9.4g} um{extra}, wall {float(r['wall']):.3f} s"
        )
    return lines
