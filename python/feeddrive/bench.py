"""`make bench`: speed, accuracy and memory of the FMU, written as a Markdown table.

Not a test: it measures and prints (targets from the developers' guide are shown beside the
measured figures; a miss is reported, not hidden)."""
from __future__ import annotations

import argparse
import platform
import statistics
import time
from pathlib import Path

import numpy as np

from .experiments.references import sinusoid
from .fmu import Plant
from .paper import paper_parameters
from .simulate import simulate_closed_loop
from .validation.controllers import make_controller, state_space_spec


def _closed_loop(interface: str, tolerance: float, ref) -> tuple[float, dict]:
    ctrl = make_controller(state_space_spec(), ref.x)
    with Plant(paper_parameters(), interface=interface, tolerance=tolerance) as plant:
        t0 = time.perf_counter()
        res = simulate_closed_loop(plant, ctrl, ref.n, float(ref.x[0]))
        wall = time.perf_counter() - t0
    return wall, dict(res)


def python_rows(repeats: int = 5) -> tuple[list[tuple[str, str, str]], dict]:
    """The 6 s, 30 mm closed-loop sinusoid driven from Python (CS and ME)."""
    ref = sinusoid(0.030, 6.0, 0.150, 6.0)
    walls = []
    res_cs = None
    for _ in range(repeats):
        w, res_cs = _closed_loop("cs", 1e-6, ref)
        walls.append(w)
    w_cs = min(walls)
    w_me, res_me = _closed_loop("me", 1e-6, ref)
    _, res_ref = _closed_loop("me", 1e-10, ref)
    dx = float(np.max(np.abs(res_cs["x"] - res_ref["x"])))
    dF = float(np.max(np.abs(res_cs["F_friction"] - res_ref["F_friction"])))
    dx_me = float(np.max(np.abs(res_me["x"] - res_ref["x"])))
    n = ref.n
    calls = 3 * n   # set inputs, doStep, get outputs per sample
    rows = [
        ("6 s closed loop from Python, CS (best of %d)" % repeats,
         f"{w_cs * 1e3:.0f} ms wall, {6.0 / w_cs:.0f}x real time", "<= 200 ms (>= 30x)"),
        ("  median of the repeats", f"{statistics.median(walls) * 1e3:.0f} ms", ""),
        ("  FMI calls per run (CS)", f"{calls} ({calls / n:.0f} per sample)", ""),
        ("  friction switch events per run", f"{int(res_cs['state_events'])}", ""),
        ("  integrator steps / RHS evaluations", f"{int(res_cs['stats.n_steps'])} / {int(res_cs['stats.n_rhs'])}", ""),
        ("6 s closed loop from Python, ME + fmpy CVode (rtol 1e-6)", f"{w_me:.2f} s wall", "reference path"),
        ("accuracy: CS (tol 1e-6) vs ME CVode rtol 1e-10, max abs(dx)", f"{dx * 1e6:.3f} um", "<= 0.5 um"),
        ("accuracy: CS vs ME rtol 1e-10, max abs(dF_friction)", f"{dF:.3f} N", ""),
        ("accuracy: ME rtol 1e-6 vs ME rtol 1e-10, max abs(dx)", f"{dx_me * 1e6:.3f} um", ""),
    ]
    return rows, {"wall_cs": w_cs, "dx": dx}


def c_rows() -> list[tuple[str, str, str]]:
    """Figures of the C drivers (co-simulation from C, doStep latency, memory), if built."""
    try:
        from .bench_c import c_benchmark_rows
    except ImportError:
        return [("C benchmarks", "not available (feeddrive.bench_c missing)", "")]
    return c_benchmark_rows()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default="build/bench.md")
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args(argv)
    rows, _ = python_rows(a.repeats)
    rows += c_rows()
    lines = [f"# feeddrive benchmark ({platform.node()}, {platform.processor() or platform.machine()}, "
             f"{time.strftime('%Y-%m-%d %H:%M')})", "",
             "| what | measured | target |", "|---|---|---|"]
    lines += [f"| {a_} | {b} | {c} |" for a_, b, c in rows]
    text = "\n".join(lines) + "\n"
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
