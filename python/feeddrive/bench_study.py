"""`make bench` rows of the parameter studies: Plant memory and start time with the shared
FMU extraction against one extraction per instance (as every Plant did before), and a
1 000-run study on LocalClusters of 1 and 2 workers (runs/s, per-run cost, scheduler and
batching overhead, peak memory per worker, the share of their cores the workers got on a
machine others use too, speed-up)."""

from __future__ import annotations

import gc
import multiprocessing
import os
import resource
import shutil
import tempfile
import time
from pathlib import Path
from typing import Any

from distributed import LocalCluster
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from .fmu import Plant, fmu_path
from .study import parse_study, run_study


def _rss_bytes() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def _peak_rss_kib() -> int:
    """Peak resident memory of this process [KiB] (run on each Dask worker)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss


def _cpu_s() -> float:
    """CPU time of this process so far [s] (user + system; run on each Dask worker)."""
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _own_extraction_instance() -> tuple[FMU2Slave, str, dict]:
    """An instance the way every Plant made one before the shared extraction: its own
    extraction, model description (kept, with its variables by name) and library copy (the
    former Plant.__init__ + start)."""
    md = read_model_description(str(fmu_path()))
    d = tempfile.mkdtemp(prefix="feeddrive_bench_")
    extract(str(fmu_path()), d)
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=d,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="bench",
    )
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    return fmu, d, {v.name: v for v in md.modelVariables}


def _per_instance(own: bool, n: int = 100) -> tuple[float, float]:
    """(resident memory per live instance [KiB], create + start + close time [ms]) of
    started Plants (``own``: instances with their own extraction, as before)."""

    def make() -> Any:
        return _own_extraction_instance() if own else _started_plant()

    def close(obj: Any) -> None:
        if own:
            _free_own(obj)
        else:
            obj.close()

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


STUDY_BENCH = {
    "schema": "feeddrive.study/1",
    "name": "bench",
    "experiment": {
        "reference": {
            "type": "sinusoid",
            "amplitude": 0.002,
            "period": 0.2,
            "centre": 0.15,
            "duration": 0.2,
        },
        "controller": {"type": "pid"},
        "half_width": 0.02,
    },
    "parameters": {
        "m": {"relative": 0.2},
        "friction.F_s": {"low": 22.0, "high": 32.0},
        "friction.sigma2": {"relative": 0.5},
    },
    "design": {"type": "lhs", "seed": 1},
    "metrics": ["reversal_error", "rms_error", "max_error"],
}


def study_rows(n_runs: int = 1000) -> list[tuple[str, str, str]]:
    """Plant memory and start time (shared extraction vs one per instance) and a study of
    ``n_runs`` 0.2 s closed loops on LocalClusters of 1 and 2 workers (started beforehand)."""
    with multiprocessing.get_context("spawn").Pool(1) as pool:  # a fresh process each
        kib_own, ms_own = pool.apply(_per_instance, (True,))
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        kib, ms = pool.apply(_per_instance, (False,))
    rows = [
        (
            "Plant: memory per live instance, shared extraction (one extraction per FMU file)",
            f"{kib:.0f} KiB (one extraction per instance, as before: {kib_own:.0f} KiB)",
            "<= 64 KiB",
        ),
        (
            "Plant: create + start + close, shared extraction",
            f"{ms:.1f} ms (one extraction per instance: {ms_own:.1f} ms)",
            "",
        ),
    ]
    doc = dict(STUDY_BENCH, design={"type": "lhs", "runs": n_runs, "seed": 1})
    study = parse_study(doc, "bench study", Path("."))
    walls: dict[int, float] = {}
    cpu_per_run: dict[int, float] = {}
    out_root = Path(tempfile.mkdtemp(prefix="feeddrive_bench_study_"))
    try:
        for workers in (1, 2):
            t0 = time.perf_counter()
            with LocalCluster(
                n_workers=workers, threads_per_worker=1, dashboard_address=None, host="127.0.0.1"
            ) as cluster:
                with cluster.get_client() as client:
                    client.run(_peak_rss_kib)  # workers import feeddrive (warm-up)
                    cpu0 = sum(client.run(_cpu_s).values())
                start = time.perf_counter() - t0
                res = run_study(study, out_root / str(workers), scheduler=cluster.scheduler_address)
                with cluster.get_client() as client:
                    peak = max(client.run(_peak_rss_kib).values())
                    cpu = sum(client.run(_cpu_s).values()) - cpu0
            share = cpu / (workers * res.wall_s)
            cpu_per_run[workers] = cpu / len(res.rows)
            walls[workers] = res.wall_s
            run_cost = sum(r["wall_s"] for r in res.rows) / len(res.rows)
            overhead = (workers * res.wall_s / len(res.rows) - run_cost) / run_cost
            rows.append(
                (
                    f"study of {n_runs} runs (0.2 s closed loop each, PID, LHS), "
                    f"{workers} local worker{'s' if workers > 1 else ''}",
                    f"{res.wall_s:.1f} s, {n_runs / res.wall_s:.0f} runs/s, "
                    f"{res.failed} failed (cluster start + worker imports {start:.1f} s, not "
                    f"counted); the workers had {share:.0%} of their cores",
                    "",
                )
            )
            rows.append(
                (
                    "  per-run cost in the worker (wall / CPU) / scheduler + batching overhead",
                    f"{run_cost * 1e3:.1f} / {cpu_per_run[workers] * 1e3:.1f} ms / "
                    f"{overhead:.1%} of a run",
                    "< 5 %",
                )
            )
            rows.append(("  peak resident memory per worker", f"{peak / 1024:.0f} MiB", ""))
    finally:
        shutil.rmtree(out_root, ignore_errors=True)
    rows.append(
        (
            "study speed-up, 2 workers over 1 (with whole cores: 2 x the ratio of CPU per run)",
            f"{walls[1] / walls[2]:.2f}x ({2 * cpu_per_run[1] / cpu_per_run[2]:.2f}x)",
            ">= 1.8x",
        )
    )
    return rows
