"""The scenario every importer runs (tests/test_cs_importers.py, test_fmi_sim.py, test_ecos.py):
the open-loop input u(t_k) = 0.5 sin(2 pi t_k) V held over each 0.5 ms sample, F_ext = 0, 2 s
from rest at x = 0.15 m (about 57 mm of travel, 0.2 m/s peak, stick and slip at every
reversal), outputs on the grid t_k = k Ts; and fmpy's runs of it (CS at the experiment
tolerance 1e-6, ME with CVode at 1e-9), computed once per session and FMU file.
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from feeddrive.fmu import Plant
from feeddrive.harness.simulate import simulate_open_loop

SECONDS = 2.0
TS = 5e-4
X0 = 0.15
AMP, FREQ = 0.5, 1.0
COLUMNS = ("x", "v", "F_friction", "i")
N = int(round(SECONDS / TS))


def grid() -> np.ndarray:
    """t_k = k Ts, k = 0..N (as every importer's loop computes it: k * Ts)."""
    return np.arange(N + 1) * TS


def u_input(t: np.ndarray) -> np.ndarray:
    """u(t_k) [V]."""
    return AMP * np.sin(2 * np.pi * FREQ * t)


@functools.cache
def fmpy_runs(fmu: Path) -> dict[str, dict[str, np.ndarray]]:
    """fmpy's CS and ME runs of the scenario (feeddrive.harness.simulate: row k holds the
    outputs at t_k after that instant's current-loop sample)."""
    t = grid()
    runs = {}
    for iface, tol in (("cs", 1e-6), ("me", 1e-9)):
        with Plant(interface=iface, tolerance=tol, path=fmu) as p:
            r = simulate_open_loop(p, t, u_input(t), start_values={"x": X0, "v": 0.0})
            runs[iface] = {c: np.asarray(r[c]) for c in ("time", *COLUMNS)}
    return runs


def end_of_step_to_sampled(i: np.ndarray) -> np.ndarray:
    """A host that reads the outputs at the end of each step holds at row k + 1 the current of
    sample k (the left limit at t_k+1); shift it to row k, the harness's Eq. 2 i[k]."""
    return np.concatenate((i[1:], i[-1:]))


def max_dev(a, b, columns=COLUMNS) -> dict[str, float]:
    """max |a[c] - b[c]| per column."""
    return {c: float(np.max(np.abs(np.asarray(a[c]) - np.asarray(b[c])))) for c in columns}
