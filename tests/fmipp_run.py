"""Run the importer scenario in FMI++ (fmipp) in this process: ME, then CS (see
tests/test_fmipp.py, which runs this file in its own process).

Usage: python tests/fmipp_run.py FMU OUT_DIR  -> OUT_DIR/fmipp.npz (me_x, me_v, ..., cs_x, ...)
"""

from __future__ import annotations

import sys
from pathlib import Path

import fmipp
import numpy as np

from importer_scenario import COLUMNS, TS, X0, N, end_of_step_to_sampled, grid, u_input

EVENT_PRECISION = 1e-12  #: [s] fmipp's event search precision (ME)
MODEL = "LinearMotorFeedDrive"


def _run(fmu_path: Path, tmp: Path, interface: str) -> dict[str, np.ndarray]:
    tmp.mkdir(parents=True, exist_ok=True)
    uri = fmipp.extractFMU(str(fmu_path), str(tmp))
    t, u = grid(), u_input(grid())
    if interface == "cs":
        f = fmipp.FMUCoSimulationV2(uri, MODEL, False, 1e-6)
        assert f.instantiate("fmipp_cs", 0.0, False, False) == fmipp.statusOK
    else:
        f = fmipp.FMUModelExchangeV2(uri, MODEL, False, True, EVENT_PRECISION, fmipp.integratorDP)
        assert f.instantiate("fmipp_me") == fmipp.statusOK
    for name, value in (("x", X0), ("v", 0.0), ("u", float(u[0]))):
        f.setRealValue(name, value)
    ok = f.initialize(0.0, False, 0.0) if interface == "cs" else f.initialize(True, 1e-6)
    assert ok == fmipp.statusOK
    out = np.empty((N + 1, len(COLUMNS)))
    out[0] = [f.getRealValue(c) for c in COLUMNS]
    for k in range(N):
        f.setRealValue("u", float(u[k]))
        if interface == "cs":
            assert f.doStep(k * TS, TS, True) == fmipp.statusOK, f"doStep at {k * TS}"
        else:
            calls = 0
            while f.getTime() < t[k + 1] - EVENT_PRECISION:  # it stops before every event
                f.integrate(float(t[k + 1]), 1e-5)
                calls += 1
                assert calls < 1000, f"fmipp ME stuck at t = {f.getTime()!r}"
        out[k + 1] = [f.getRealValue(c) for c in COLUMNS]
    d = {c: out[:, j] for j, c in enumerate(COLUMNS)}
    d["i"] = end_of_step_to_sampled(d["i"])
    return d


def main(fmu: str, out_dir: str) -> None:
    out = Path(out_dir)
    # ME first: fmipp's ModelManager keeps the model description parsed for the first instance
    # of a model identifier; an ME instance after a CS one of the same model aborts
    runs = {k: _run(Path(fmu), out / k, k) for k in ("me", "cs")}
    np.savez(out / "fmipp.npz", **{f"{k}_{c}": v for k, d in runs.items() for c, v in d.items()})


if __name__ == "__main__":
    main(*sys.argv[1:])
