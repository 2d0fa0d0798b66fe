#!/usr/bin/env python3
"""Write the example recording examples/runs/sinusoid.csv (+ its sidecar .json): a virtual
measurement made by the FMU as `feeddrive experiments` makes its runs — the paper's model in
closed loop under the paper-designed state-space controller, a 10 mm sinusoid of 2 s period at
mid-stroke (one bottom-to-bottom cycle, 2 s at 0.5 ms), the 100 nm scale and 5 mA current noise.

Values are rounded below the sensors' resolution (time 0.1 us, positions 1 nm, the reference 10 nm, u 10 uV, i 10 uA)
so that the CSV stays small (< 200 KB).

Usage: example_run.py [OUT.csv]   (default examples/runs/sinusoid.csv)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from feeddrive.data import Run, write_run
from feeddrive.experiments.recording import closed_loop_measurement
from feeddrive.harness import Sensors, sinusoid
from feeddrive.model_file import paper_model

ROOT = Path(__file__).resolve().parents[1]
DIGITS = {"time": 7, "u": 5, "i": 5, "x": 9, "x_ref": 8, "F_load": 6}


def example_run() -> Run:
    """The example recording (deterministic: fixed noise seed)."""
    ref = sinusoid(0.010, 2.0, 0.150, 2.0)
    run = closed_loop_measurement(
        paper_model().fmu_parameters(),
        Sensors(seed=7),
        ref,
        {"name": "sinusoid", "amplitude": 0.010, "period": 2.0, "centre": 0.150},
    )
    cols = {k: (None if v is None else np.round(v, DIGITS[k])) for k, v in run.columns().items()}
    return Run(**cols, meta=run.meta)


def main() -> int:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "examples" / "runs" / "sinusoid.csv"
    write_run(example_run(), out)
    print(f"wrote {out} ({out.stat().st_size // 1024} KiB) and {out.with_suffix('.json').name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
