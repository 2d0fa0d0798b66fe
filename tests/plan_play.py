"""A drive that plays a plan: every planned run simulated on the FMU, recorded as runs in the recording format.

What a user does with ``feeddrive plan``'s folder, with the FMU (at a truth's parameters) as
the machine: each reference of ``DIR/reference`` is played (closed loop under the sidecar's
controller, after the sidecar's settling hold with the load hung; open loop from rest at the
sidecar's position, stopped where the stage leaves the sidecar's ``stop_outside``), the
recording gets the sensors' effects (100 nm scale, current noise acting on the stage), and is
written as ``NAME.csv`` with the plan's sidecar copied beside it unchanged.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from feeddrive.data import Run, write_run
from feeddrive.experiments.recording import closed_loop_measurement, run_seed, sampled_signals
from feeddrive.fmu import Plant
from feeddrive.harness.references import from_positions
from feeddrive.harness.runs import to_run
from feeddrive.harness.sensors import Sensors
from feeddrive.harness.simulate import simulate_open_loop


def read_reference(path: Path) -> dict[str, np.ndarray]:
    """The columns of a plan's reference CSV."""
    with open(path, encoding="ascii") as f:
        names = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {n: data[:, j] for j, n in enumerate(names)}


def _open_loop(
    params: Mapping[str, Any],
    sensors: Sensors,
    cols: dict[str, np.ndarray],
    side: Mapping[str, Any],
) -> Run:
    Ts = float(side["Ts"])
    u = np.append(cols["u"], cols["u"][-1])  # one sample more (sampled_signals)
    t = np.arange(len(u)) * Ts
    F = sensors.force_disturbance(len(u))
    with Plant(params, interface="cs", tolerance=1e-6) as plant:
        res = sampled_signals(
            simulate_open_loop(
                plant, t, u, F_ext=F, start_values={"x": float(side["position"]), "v": 0.0}
            )
        )
    lo, hi = (float(v) for v in side["stop_outside"])
    out = np.flatnonzero((res["x"] < lo) | (res["x"] > hi))
    stop = int(out[0]) if out.size else len(res["x"])
    return to_run({k: v[:stop] for k, v in res.items()}, sensors, x_ref=None, F_load=0.0)


def play_plan(plan_dir: Path, params: Mapping[str, Any], out: Path, seed: int = 0) -> list[Path]:
    """Record every run of ``plan_dir`` on the plant ``params`` into ``out``; the CSV paths."""
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for ref_path in sorted((plan_dir / "reference").glob("*.csv")):
        side_path = plan_dir / "sidecar" / f"{ref_path.stem}.json"
        side = json.loads(side_path.read_text(encoding="utf-8"))
        cols = read_reference(ref_path)
        sensors = Sensors(seed=run_seed(seed, ref_path.stem))
        if "x_ref" in cols:
            ref = from_positions(cols["x_ref"], float(side["Ts"]))
            run = closed_loop_measurement(
                params,
                sensors,
                ref,
                {},
                spec=side["controller"],
                F_load=float(side["F_load"]),
                u_ff=cols.get("u_add"),
                hold=float(side["hold_before_record"]),
            )
        else:
            run = _open_loop(params, sensors, cols, side)
        run.meta = {}
        path = out / f"{ref_path.stem}.csv"
        write_run(run, path)
        shutil.copyfile(side_path, out / side_path.name)
        paths.append(path)
    return paths
