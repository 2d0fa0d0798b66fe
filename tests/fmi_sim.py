"""Test harness: run an FMU in the Rust ``fmi-sim`` (crates.io fmi-sim 0.7.0, "a pure Rust FMI
simulator", FMI 2.0 and 3.0, CS and ME), installed by ``make importers`` (``cargo install
--locked``) and linked as build/importers/fmi-sim; when it could not be installed, make wrote
the one-line reason to build/importers/fmi-sim.skip.

fmi-sim's loops (src/sim/fmi2/cs.rs, src/sim/me.rs):
* CS: t_k = t0 + k h (h = ``--output-interval``); record the outputs at t_k, set the inputs
  at t_k (linear interpolation of the input CSV: at a grid point u_k-1 + 1.0 (u_k - u_k-1),
  u_k to the last bit), ``fmi2DoStep(t_k, h)``.  Outputs are read at the end of each step.
* ME: forward Euler with step h = ``--output-interval`` (its only solver), shortened to the
  FMU's next time event; a state event is detected when an indicator changed sign over a
  step, not located; the inputs are interpolated after each step, before the event update.
  Outputs are recorded after every step and before every event update (rows may repeat a
  time); :func:`on_grid` takes the last row at each grid time.

Nothing here is FMI-version specific: the same call runs an FMI 3.0 FMU (its variables by
the same names).
"""

from __future__ import annotations

import subprocess
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from pyarrow import csv as pacsv

REPO = Path(__file__).resolve().parents[1]
VERSION = "0.7.0"
EXE = REPO / "build" / "importers" / "fmi-sim"  # make importers: link to the binary
SKIP = REPO / "build" / "importers" / "fmi-sim.skip"  # make importers: why it is missing


def fmi_sim_exe() -> tuple[Path | None, str]:
    """(the binary, "") when ``make importers`` installed it, else (None, the reason)."""
    if EXE.exists():
        return EXE, ""
    if SKIP.is_file():
        return None, SKIP.read_text().strip().splitlines()[0]
    return (
        None,
        f"fmi-sim {VERSION} is not installed: run `make importers` (cargo install from crates.io)",
    )


def run_fmi_sim(
    exe: Path,
    fmu: Path,
    interface: str,
    t: np.ndarray,
    inputs: Mapping[str, np.ndarray],
    start_values: Mapping[str, float],
    out_dir: Path,
    step: float | None = None,
    tolerance: float = 1e-6,
) -> dict[str, np.ndarray]:
    """Run ``fmu`` in fmi-sim from t[0] to t[-1]; returns its output CSV's columns by name.

    interface : "cs" or "me".
    inputs : input name -> values at ``t`` (written as fmi-sim's input CSV).
    step : CS communication step / ME Euler step and output interval (default t[1] - t[0]).
    tolerance : passed to the FMU (fmi2SetupExperiment / fmi3Enter...Mode).
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    names = list(inputs)
    inp, out = out_dir / f"input_{interface}.csv", out_dir / f"output_{interface}.csv"
    cols = np.column_stack([t, *(np.asarray(inputs[n], dtype=float) for n in names)])
    np.savetxt(
        inp, cols, delimiter=",", header=",".join(["time", *names]), comments="", fmt="%.17g"
    )
    h = float(t[1] - t[0]) if step is None else step
    cmd = [
        str(exe),
        "--model",
        str(fmu),
        "-i",
        str(inp),
        "-o",
        str(out),
        {"cs": "co-simulation", "me": "model-exchange"}[interface],
        "-s",
        repr(float(t[0])),
        "-f",
        repr(float(t[-1])),
        "--output-interval",
        repr(h),
        "--tolerance",
        repr(tolerance),
    ]
    for k, v in start_values.items():
        cmd += ["--init-values", f"{k}={v!r}"]
    # stdout: a line per recorded row; errors go to stderr
    p = subprocess.run(
        cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, timeout=600
    )
    assert p.returncode == 0, f"{' '.join(cmd)}\n{p.stderr[-3000:]}"
    table = pacsv.read_csv(out)
    return {c: table.column(c).to_numpy().astype(float) for c in table.column_names}


def on_grid(
    run: Mapping[str, np.ndarray], t: np.ndarray, columns: Sequence[str], tol: float = 1e-9
) -> dict[str, np.ndarray]:
    """The last recorded row at each time of ``t`` (within ``tol`` s): after the event update
    there, when the run recorded that instant more than once."""
    times = run["time"]
    last = np.searchsorted(times, t + tol, side="right") - 1
    assert np.all(last >= 0) and np.all(np.abs(times[last] - t) <= tol), (
        "fmi-sim did not record every grid time"
    )
    return {c: np.asarray(run[c])[last] for c in columns}
