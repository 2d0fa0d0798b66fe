"""Run the importer scenario's co-simulation in FMI++ (fmipp) with parameters set by name
(tests/test_export_fmu.py runs this file in its own process: fmipp keeps the first model
description it parsed for a model identifier).

Usage: python tests/fmipp_export_run.py FMU OUT.npz [PARAMETERS.json]
PARAMETERS.json: {name: value} set before initialization (bool: Boolean, int: Integer, float: Real).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import fmipp
import numpy as np

from importer_scenario import COLUMNS, TS, X0, N, grid, u_input

MODEL = "LinearMotorFeedDrive"


def run(fmu_path: Path, out: Path, parameters: dict) -> None:
    tmp = out.parent / f"{out.stem}_unzipped"
    tmp.mkdir(parents=True, exist_ok=True)
    uri = fmipp.extractFMU(str(fmu_path), str(tmp))
    u = u_input(grid())
    f = fmipp.FMUCoSimulationV2(uri, MODEL, False, 1e-6)
    assert f.instantiate("fmipp_cs", 0.0, False, False) == fmipp.statusOK, "instantiate"
    for name, value in parameters.items():
        if isinstance(value, bool):
            ok = f.setBooleanValue(name, value)
        elif isinstance(value, int):
            ok = f.setIntegerValue(name, value)
        else:
            ok = f.setRealValue(name, float(value))
        assert ok == fmipp.statusOK, f"set {name} = {value!r}"
    for name, value in (("x", X0), ("v", 0.0), ("u", float(u[0]))):
        f.setRealValue(name, value)
    assert f.initialize(0.0, False, 0.0) == fmipp.statusOK, "initialize"
    rows = np.empty((N + 1, len(COLUMNS)))
    rows[0] = [f.getRealValue(c) for c in COLUMNS]
    for k in range(N):
        f.setRealValue("u", float(u[k]))
        assert f.doStep(k * TS, TS, True) == fmipp.statusOK, f"doStep at {k * TS}"
        rows[k + 1] = [f.getRealValue(c) for c in COLUMNS]
    np.savez(out, **{c: rows[:, j] for j, c in enumerate(COLUMNS)})


if __name__ == "__main__":
    params = json.loads(Path(sys.argv[3]).read_text()) if len(sys.argv) > 3 else {}
    run(Path(sys.argv[1]), Path(sys.argv[2]), params)
