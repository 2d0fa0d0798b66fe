"""`make bench`: speed, accuracy and memory of the FMU, written as a Markdown table.

Not a test: it measures and prints (targets from the developers' guide are shown beside the
measured figures; a miss is reported, not hidden)."""
from __future__ import annotations

import argparse
import gc
import multiprocessing
import os
import platform
import resource
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
from distributed import LocalCluster
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from .bench_c import run_bench_cs, run_cycles
from .fmu import Plant, fmu_path
from .harness.controllers import make_controller, state_space_spec
from .harness.references import sinusoid
from .harness.simulate import simulate_closed_loop
from .paper import paper_parameters
from .study import parse_study, run_study


def _closed_loop(interface: str, tolerance: float, ref) -> tuple[float, dict]:
    ctrl = make_controller(state_space_spec(), ref)
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


def c_rows(bench_cs: Path, cycles: Path | None, library: Path,
           repeats: int = 5) -> list[tuple[str, str, str]]:
    """Figures of the C hosts (built by `make bench`): co-simulation from C, doStep latency, memory."""
    f = run_bench_cs(bench_cs, library, repeats)
    wall = f["wall_s_best"]
    rows = [
        ("6 s closed loop from C through fmi2DoStep (best of %d)" % repeats,
         f"{wall * 1e3:.1f} ms wall, {6.0 / wall:.0f}x real time", "<= 3 ms (>= 2000x)"),
        ("  steps / RHS evaluations / friction events", f"{f['solver_steps']} / {f['rhs_evaluations']} / "
         f"{f['state_events']}", ""),
        ("  friction events per simulated s / per wall s", f"{f['state_events_per_sim_s']:.1f} / "
         f"{f['state_events_per_wall_s']:.0f}", ""),
        ("one 0.5 ms fmi2DoStep: median", f"{f['dostep_us_median']:.2f} us", ""),
        ("one 0.5 ms fmi2DoStep: 99th percentile", f"{f['dostep_us_p99']:.2f} us", "< 20 us"),
        ("one 0.5 ms fmi2DoStep: maximum (includes scheduler preemption)", f"{f['dostep_us_max']:.1f} us", ""),
    ]
    if cycles is None:
        return rows + [("memory", "not measured (no --cycles host given)", "")]
    try:
        m = run_cycles(cycles, library, 10_000)
    except (RuntimeError, FileNotFoundError) as e:
        return rows + [("memory", f"not measured ({e})", "")]
    if "peak_bytes" in m:
        rows.append(("memory of one instance (peak held through the FMI callbacks, incl. an FMU state copy)",
                     f"{m['peak_bytes'] / 1024:.1f} KiB", "< 64 KiB"))
    if "rss_growth_kib" in m:
        rows.append(("resident memory growth over 10 000 instantiate/simulate/free cycles",
                     f"{m['rss_growth_kib']} KiB", "no growth"))
    return rows


def _rss_bytes() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def _peak_rss_kib() -> int:
    """Peak resident memory of this process [KiB] (run on each Dask worker)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss


def _own_extraction_instance() -> tuple[FMU2Slave, str, dict]:
    """An instance the way every Plant made one before the shared extraction: its own
    extraction, model description (kept, with its variables by name) and library copy (the
    former Plant.__init__ + start)."""
    md = read_model_description(str(fmu_path()))
    d = tempfile.mkdtemp(prefix="feeddrive_bench_")
    extract(str(fmu_path()), d)
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=d, modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName="bench")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    return fmu, d, {v.name: v for v in md.modelVariables}


def _per_instance(own: bool, n: int = 100) -> tuple[float, float]:
    """(resident memory per live instance [KiB], create + start + close time [ms]) of
    started Plants (``own``: instances with their own extraction, as before)."""
    make, close = (_own_extraction_instance, _free_own) if own else (_started_plant, Plant.close)
    close(make())
    gc.collect()
    r0 = _rss_bytes()
    live = [make() for _ in range(n)]
    kib = (_rss_bytes() - r0) / n / 1024
    for obj in live:
        close(obj)
    t0 = time.perf_counter()
    for _ in range(n):
        close(make())
    return kib, (time.perf_counter() - t0) / n * 1e3


def _started_plant() -> Plant:
    p = Plant()
    p.start()
    return p


def _free_own(obj: tuple[FMU2Slave, str, dict]) -> None:
    obj[0].terminate()
    obj[0].freeInstance()
    shutil.rmtree(obj[1], ignore_errors=True)


STUDY_BENCH = {"schema": "feeddrive.study/1", "name": "bench",
               "experiment": {"reference": {"type": "sinusoid", "amplitude": 0.002,
                                            "period": 0.2, "centre": 0.15, "duration": 0.2},
                              "controller": {"type": "pid"}, "half_width": 0.02},
               "parameters": {"m": {"relative": 0.2}, "friction.F_s": {"low": 22.0, "high": 32.0},
                              "friction.sigma2": {"relative": 0.5}},
               "design": {"type": "lhs", "seed": 1},
               "metrics": ["reversal_error", "rms_error", "max_error"]}


def study_rows(n_runs: int = 1000) -> list[tuple[str, str, str]]:
    """Plant memory and start time (shared extraction vs one per instance) and a study of
    ``n_runs`` 0.2 s closed loops on LocalClusters of 1 and 2 workers (started beforehand)."""
    with multiprocessing.get_context("spawn").Pool(1) as pool:    # a fresh process each
        kib_own, ms_own = pool.apply(_per_instance, (True,))
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        kib, ms = pool.apply(_per_instance, (False,))
    rows = [("Plant: memory per live instance, shared extraction (one extraction per FMU file)",
             f"{kib:.0f} KiB (one extraction per instance, as before: {kib_own:.0f} KiB)",
             "<= 64 KiB"),
            ("Plant: create + start + close, shared extraction",
             f"{ms:.1f} ms (one extraction per instance: {ms_own:.1f} ms)", "")]
    doc = dict(STUDY_BENCH, design={"type": "lhs", "runs": n_runs, "seed": 1})
    study = parse_study(doc, "bench study", Path("."))
    walls: dict[int, float] = {}
    out_root = Path(tempfile.mkdtemp(prefix="feeddrive_bench_study_"))
    try:
        for workers in (1, 2):
            t0 = time.perf_counter()
            with LocalCluster(n_workers=workers, threads_per_worker=1, dashboard_address=None,
                              host="127.0.0.1") as cluster:
                with cluster.get_client() as client:
                    client.run(_peak_rss_kib)          # workers import feeddrive (warm-up)
                start = time.perf_counter() - t0
                res = run_study(study, out_root / str(workers), scheduler=cluster.scheduler_address)
                with cluster.get_client() as client:
                    peak = max(client.run(_peak_rss_kib).values())
            walls[workers] = res.wall_s
            run_cost = sum(r["wall_s"] for r in res.rows) / len(res.rows)
            overhead = (workers * res.wall_s / len(res.rows) - run_cost) / run_cost
            rows.append((f"study of {n_runs} runs (0.2 s closed loop each, PID, LHS), "
                         f"{workers} local worker{'s' if workers > 1 else ''}",
                         f"{res.wall_s:.1f} s, {n_runs / res.wall_s:.0f} runs/s, "
                         f"{res.failed} failed (cluster start + worker imports {start:.1f} s, not "
                         f"counted)", ""))
            rows.append(("  per-run cost in the worker / scheduler + batching overhead per run",
                         f"{run_cost * 1e3:.1f} ms / {overhead:.1%} of a run", "< 5 %"))
            rows.append(("  peak resident memory per worker", f"{peak / 1024:.0f} MiB", ""))
    finally:
        shutil.rmtree(out_root, ignore_errors=True)
    rows.append(("study speed-up, 2 workers over 1", f"{walls[1] / walls[2]:.2f}x", ">= 1.8x"))
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default="build/bench.md")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--bench-cs", default=None, help="the built tests/c bench_cs host (`make bench` passes it)")
    ap.add_argument("--cycles", default=None, help="the built tests/c cycles host (memory figures)")
    ap.add_argument("--library", default=None, help="the FMU's shared library the C hosts load")
    ap.add_argument("--study-runs", type=int, default=1000, help="runs of the benchmark study")
    a = ap.parse_args(argv)
    if a.bench_cs and not a.library:
        ap.error("--bench-cs needs --library (the FMU's .so)")
    rows, _ = python_rows(a.repeats)
    rows += study_rows(a.study_runs)
    if a.bench_cs:
        rows += c_rows(Path(a.bench_cs), Path(a.cycles) if a.cycles else None, Path(a.library), a.repeats)
    else:
        rows.append(("C benchmark hosts", "not measured (no --bench-cs given; `make bench` builds and passes it)", ""))
    lines = [f"# feeddrive benchmark ({platform.node()}, {platform.machine()}, {os.cpu_count()} cores, "
             f"{time.strftime('%Y-%m-%d %H:%M')}, load average {os.getloadavg()[0]:.1f})", "",
             "| what | measured | target |", "|---|---|---|"]
    lines += [f"| {a_} | {b} | {c} |" for a_, b, c in rows]
    text = "\n".join(lines) + "\n"
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
