"""`make bench`: speed, accuracy and memory of the FMU (and the size of the default
campaign), written as a Markdown table.

Not a test: it measures and prints (targets from the developers' guide are shown beside the
measured figures; a miss is reported, not hidden)."""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from .bench_agreement import agreement_figures, agreement_rows
from .bench_c import instructions_per_sample, run_bench_cs, run_cycles, run_two_fmus
from .bench_campaign import campaign_rows
from .bench_cli import help_rows
from .bench_engines import engine_rows
from .bench_study import study_rows
from .data import Run, write_run
from .effects import Structure, structure_off
from .fmu import Plant
from .harness.controller_fmu import ControllerFMU, controller_fmu_parameters, sinusoid_source
from .harness.controllers import make_controller, state_space_spec
from .harness.references import sinusoid
from .harness.runs import closed_loop_run, run_closed_loop
from .harness.sensors import Sensors
from .harness.simulate import simulate_closed_loop
from .harness.two_fmus import simulate_two_fmus
from .paper import paper_parameters


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
    runs = [_closed_loop("cs", 1e-6, ref) for _ in range(repeats)]
    walls = [w for w, _ in runs]
    res_cs = runs[-1][1]
    w_cs = min(walls)
    w_me, res_me = _closed_loop("me", 1e-6, ref)
    _, res_ref = _closed_loop("me", 1e-10, ref)
    dx = float(np.max(np.abs(res_cs["x"] - res_ref["x"])))
    dF = float(np.max(np.abs(res_cs["F_friction"] - res_ref["F_friction"])))
    dx_me = float(np.max(np.abs(res_me["x"] - res_ref["x"])))
    n = ref.n
    calls = 3 * n  # set inputs, doStep, get outputs per sample
    rows = [
        (
            f"6 s closed loop from Python, CS (best of {repeats})",
            f"{w_cs * 1e3:.0f} ms wall, {6.0 / w_cs:.0f}x real time",
            "<= 200 ms (>= 30x)",
        ),
        ("  median of the repeats", f"{statistics.median(walls) * 1e3:.0f} ms", ""),
        ("  FMI calls per run (CS)", f"{calls} ({calls / n:.0f} per sample)", ""),
        ("  friction switch events per run", f"{int(res_cs['state_events'])}", ""),
        (
            "  integrator steps / RHS evaluations",
            f"{int(res_cs['stats.n_steps'])} / {int(res_cs['stats.n_rhs'])}",
            "",
        ),
        (
            "6 s closed loop from Python, ME + fmpy CVode (rtol 1e-6)",
            f"{w_me:.2f} s wall",
            "reference path",
        ),
        (
            "accuracy: CS (tol 1e-6) vs ME CVode rtol 1e-10, max abs(dx)",
            f"{dx * 1e6:.3f} um",
            "<= 0.5 um",
        ),
        ("accuracy: CS vs ME rtol 1e-10, max abs(dF_friction)", f"{dF:.3f} N", ""),
        ("accuracy: ME rtol 1e-6 vs ME rtol 1e-10, max abs(dx)", f"{dx_me * 1e6:.3f} um", ""),
    ]
    return rows, {"wall_cs": w_cs, "dx": dx, "res_cs": res_cs, "res_me": res_me}


def two_fmu_rows(
    wall_python: float,
    res_python: dict,
    repeats: int = 5,
    host: Path | None = None,
    plant_library: Path | None = None,
    controller_library: Path | None = None,
) -> list[tuple[str, str, str]]:
    """The same 6 s loop as controller FMU + plant FMU, stepped from Python and,
    with the ``two_fmus`` C host, from C."""
    ref = sinusoid(0.030, 6.0, 0.150, 6.0)
    values = controller_fmu_parameters(
        state_space_spec(), quantum=1e-7, reference=sinusoid_source(0.030, 6.0, 0.150, 6.0)
    )
    runs = [
        simulate_two_fmus(paper_parameters(), values, ref.n, float(ref.x[0]))
        for _ in range(repeats)
    ]
    wall = min(float(r["wall"]) for r in runs)
    dx = float(np.max(np.abs(runs[0]["x"] - res_python["x"])))
    rows = [
        (
            f"6 s closed loop, controller FMU + plant FMU stepped from Python (best of {repeats})",
            f"{wall * 1e3:.0f} ms wall, {wall / wall_python:.2f} x the Python-controller run",
            "",
        ),
        (
            "  agreement with the Python-controller run, max abs(dx)",
            f"{dx * 1e6:.3g} um",
            "<= 0.01 um",
        ),
    ]
    if host is None or plant_library is None or controller_library is None:
        return rows + [("  from C", "not measured (no --two-fmus host given)", "")]
    with ControllerFMU(values) as c:
        typed = {k: (c.vr(k), c.vars[k].type[0], float(v)) for k, v in values.items()}
    fig, x = run_two_fmus(
        host, plant_library, controller_library, typed, ref.n, float(ref.x[0]), repeats
    )
    w = fig["wall_s_best"]
    dxc = float(np.max(np.abs(np.asarray(x) - res_python["x"])))
    return rows + [
        (
            f"6 s closed loop, controller FMU + plant FMU stepped from C (best of {repeats})",
            f"{w * 1e3:.1f} ms wall, {w / wall_python:.3f} x the Python-controller run",
            "<= 1/3",
        ),
        (
            "  agreement with the Python-controller run, max abs(dx)",
            f"{dxc * 1e6:.3g} um",
            "<= 0.01 um",
        ),
    ]


def c_rows(
    bench_cs: Path, cycles: Path | None, library: Path, repeats: int = 5
) -> list[tuple[str, str, str]]:
    """Figures of the C hosts (built by `make bench`): co-simulation from C with the per-sample
    scheme (``solver.fast``, the default) and with the adaptive DP45 throughout, doStep latency,
    instructions per sample (callgrind), memory."""
    f = run_bench_cs(bench_cs, library, repeats, "fast")
    a = run_bench_cs(bench_cs, library, repeats, "adaptive")
    wall, wall_a = f["wall_s_best"], a["wall_s_best"]
    rows = [
        (
            f"6 s closed loop from C through fmi2DoStep, per-sample scheme (best of {repeats})",
            f"{wall * 1e3:.1f} ms wall, {6.0 / wall:.0f}x real time",
            "<= 3 ms (>= 2000x)",
        ),
        (
            f"  same, its floor on a loaded machine: each 50-sample chunk's fastest of the {repeats} "
            "repetitions, summed",
            f"{f['wall_s_floor'] * 1e3:.1f} ms wall, {6.0 / f['wall_s_floor']:.0f}x real time",
            "<= 3 ms (>= 2000x)",
        ),
        (
            "  same, adaptive DP45 throughout (solver.fast = false)",
            f"{wall_a * 1e3:.1f} ms wall, {6.0 / wall_a:.0f}x real time",
            "",
        ),
        (
            "  steps / RHS evaluations / friction events (scheme; adaptive)",
            f"{f['solver_steps']} / {f['rhs_evaluations']} / {f['state_events']}; "
            f"{a['solver_steps']} / {a['rhs_evaluations']} / {a['state_events']}",
            "",
        ),
        (
            "  friction events per simulated s / per wall s",
            f"{f['state_events_per_sim_s']:.1f} / {f['state_events_per_wall_s']:.0f}",
            "",
        ),
    ]
    ipc = {m: instructions_per_sample(bench_cs, library, m) for m in ("fast", "adaptive")}
    fi, ai = ipc["fast"], ipc["adaptive"]
    if fi is not None and ai is not None:
        rows.append(
            (
                "  instructions per sample (callgrind: fmi2DoStep + fmi2GetReal + fmi2SetReal)",
                f"{fi['fmi']:.0f} (adaptive: {ai['fmi']:.0f})",
                "",
            )
        )
        rows.append(
            (
                "  of which fmi2DoStep / fmi2GetReal / fmi2SetReal",
                f"{fi.get('dostep', 0):.0f} / {fi.get('get', 0):.0f} / {fi.get('set', 0):.0f}",
                "",
            )
        )
        integ, loop = fi.get("integrators", 0.0), fi.get("loop", 0.0)
        rows.append(
            (
                "  of which the integrators alone (the RK stages with no FMI around them: "
                "fast_step + dp45_advance)",
                f"{integ:.0f} (adaptive: {ai.get('integrators', 0):.0f})",
                "",
            )
        )
        if integ > 0 and loop > 0:
            rows.append(
                (
                    "  the integrators' part of the loop's floor (wall floor x their share of the "
                    f"loop's {loop:.0f} instructions per sample, controller included)",
                    f"{f['wall_s_floor'] * integ / loop * 1e3:.1f} ms wall",
                    "the C path's floor with no FMI glue at all",
                )
            )
    else:
        rows.append(
            (
                "  instructions per sample",
                "not measured (valgrind's callgrind and callgrind_annotate not installed)",
                "",
            )
        )
    rows += [
        (
            "one 0.5 ms fmi2DoStep: median (scheme; adaptive)",
            f"{f['dostep_us_median']:.2f} us; {a['dostep_us_median']:.2f} us",
            "",
        ),
        (
            "one 0.5 ms fmi2DoStep: 99th percentile (scheme; adaptive)",
            f"{f['dostep_us_p99']:.2f} us; {a['dostep_us_p99']:.2f} us",
            "< 20 us",
        ),
        (
            "one 0.5 ms fmi2DoStep: maximum (includes scheduler preemption)",
            f"{f['dostep_us_max']:.1f} us",
            "",
        ),
    ]
    if cycles is None:
        return rows + [("memory", "not measured (no --cycles host given)", "")]
    try:
        m = run_cycles(cycles, library, 10_000)
    except (RuntimeError, FileNotFoundError) as e:
        return rows + [("memory", f"not measured ({e})", "")]
    if "peak_bytes" in m:
        rows.append(
            (
                "memory of one instance (peak held through the FMI callbacks, incl. an FMU state copy)",
                f"{m['peak_bytes'] / 1024:.1f} KiB",
                "< 64 KiB",
            )
        )
    if "rss_growth_kib" in m:
        rows.append(
            (
                "resident memory growth over 10 000 instantiate/simulate/free cycles",
                f"{m['rss_growth_kib']} KiB",
                "no growth",
            )
        )
    return rows


def fast_path_rows() -> list[tuple[str, str, str]]:
    """Accuracy of the co-simulation's per-sample scheme on the 6 s, 30 mm loop with an ideal
    scale (quantiser off) against ME CVode rtol 1e-10, for GMS and for static friction; and the
    static-friction stick case (the Sec. 3 run's top-reversal error at the
    default tolerance against rtol 1e-10, 100 nm scale)."""
    ref = sinusoid(0.030, 6.0, 0.150, 6.0)
    spec, ideal = state_space_spec(), Sensors(quantum=0.0, current_noise=0.0)
    rows = []
    static = structure_off(Structure.SLIP_ELEMENTS)  # static friction instead of GMS
    for name, change in (("GMS", {}), ("static friction", static)):
        p = {**paper_parameters(), **change}
        me = run_closed_loop(p, spec, ref, sensors=ideal, interface="me", tolerance=1e-10)
        fast = run_closed_loop(p, spec, ref, sensors=ideal)
        slow = run_closed_loop({**p, "solver.fast": False}, spec, ref, sensors=ideal)
        d = float(np.max(np.abs(fast["x"] - me["x"])))
        d_a = float(np.max(np.abs(slow["x"] - me["x"])))
        rows.append(
            (
                f"accuracy of the per-sample scheme (tol 1e-6), {name}, quantiser off, vs ME rtol 1e-10, "
                "max abs(dx)",
                f"{d * 1e6:.5f} um (adaptive DP45: {d_a * 1e6:.5f} um)",
                "<= 0.05 um",
            )
        )
    run, _ = closed_loop_run(
        paper_parameters(), spec, ref, Sensors(seed=3), experiment="sec3_sinusoid"
    )
    top, w = int(np.argmax(ref.x)), int(round(0.3 / ref.Ts))
    p = {**paper_parameters(), **static}
    peak = {
        tol: float(
            np.abs(run_closed_loop(p, spec, ref, tolerance=tol)["x"] - run.x)[
                top - w : top + w + 1
            ].max()
        )
        for tol in (1e-6, 1e-10)
    }
    rows.append(
        (
            "static-friction stick case (Sec. 3 'static friction instead of GMS', top-reversal error): "
            "default tol 1e-6 vs 1e-10",
            f"{peak[1e-6] * 1e6:.4f} vs {peak[1e-10] * 1e6:.4f} um "
            f"(difference {abs(peak[1e-6] - peak[1e-10]) * 1e6:.4f} um)",
            "<= 0.05 um",
        )
    )
    return rows


_LOAD_CHILD = (
    "import sys, time; from feeddrive.data import load_run; t0 = time.perf_counter(); "
    "run = load_run(sys.argv[1]); print(time.perf_counter() - t0, run.n)"
)
# a small interpreter between us and the loader: a child's ru_maxrss starts at its parent's
# resident size (Linux carries it over fork and exec), so the loader is not our child
_MEASURE = (
    "import resource, subprocess, sys; out = subprocess.run([sys.executable, '-c', "
    "sys.argv[1], sys.argv[2]], check=True, capture_output=True, text=True).stdout; "
    "print(out.strip(), resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)"
)


def load_rows(rows: int = 2_500_000) -> list[tuple[str, str, str]]:
    """Loading a ~200 MB recording (``rows`` rows of the six columns, written by
    :func:`feeddrive.data.write_run` into a temporary folder): MB/s and the peak resident
    memory of the process that loads it (``ru_maxrss`` of RUSAGE_CHILDREN)."""
    rng = np.random.default_rng(0)
    t = np.arange(rows) * 5e-4
    x = 0.15 + 0.03 * np.sin(2 * np.pi * t / 6.0) + 1e-7 * rng.standard_normal(rows)
    run = Run(
        time=t,
        u=rng.standard_normal(rows),
        i=rng.standard_normal(rows),
        x=x,
        x_ref=x + 1e-6 * rng.standard_normal(rows),
        F_load=np.full(rows, 54.9),
    )
    with tempfile.TemporaryDirectory(prefix="feeddrive_bench_") as d:
        path = Path(d) / "big.csv"
        write_run(run, path)
        del run, t, x
        size = path.stat().st_size
        out = subprocess.run(
            [sys.executable, "-c", _MEASURE, _LOAD_CHILD, str(path)],
            check=True,
            capture_output=True,
            text=True,
        ).stdout.split()
    wall, n, peak_kib = float(out[0]), int(out[1]), int(out[2])
    return [
        (
            f"load_run of a {size / 1e6:.0f} MB CSV ({n} rows, 6 columns)",
            f"{wall:.2f} s, {size / 1e6 / wall:.0f} MB/s",
            "",
        ),
        (
            "  peak resident memory of the loading process",
            f"{peak_kib / 1024:.0f} MiB ({peak_kib * 1024 / size:.2f}x the file)",
            "<= 3x the file",
        ),
    ]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default="build/bench.md")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument(
        "--bench-cs", default=None, help="the built tests/c bench_cs host (`make bench` passes it)"
    )
    ap.add_argument("--cycles", default=None, help="the built tests/c cycles host (memory figures)")
    ap.add_argument("--library", default=None, help="the FMU's shared library the C hosts load")
    ap.add_argument("--two-fmus", default=None, help="the built tests/c two_fmus host")
    ap.add_argument(
        "--controller-library", default=None, help="the controller FMU's shared library"
    )
    ap.add_argument("--study-runs", type=int, default=1000, help="runs of the benchmark study")
    a = ap.parse_args(argv)
    if a.bench_cs and not a.library:
        ap.error("--bench-cs needs --library (the FMU's .so)")
    study = study_rows(a.study_runs)  # first: a worker's peak RSS counts from this process's
    rows = help_rows(a.repeats)
    rows += load_rows()
    py_rows, figs = python_rows(a.repeats)
    rows += py_rows
    rows += two_fmu_rows(
        figs["wall_cs"],
        figs["res_cs"],
        a.repeats,
        *(Path(p) if p else None for p in (a.two_fmus, a.library, a.controller_library)),
    )
    rows += agreement_rows(agreement_figures(figs["res_cs"], figs["res_me"]))
    rows += study
    rows += engine_rows(figs["wall_cs"], a.repeats)
    rows += fast_path_rows()
    rows += campaign_rows()
    if a.bench_cs:
        rows += c_rows(
            Path(a.bench_cs), Path(a.cycles) if a.cycles else None, Path(a.library), a.repeats
        )
    else:
        rows.append(
            (
                "C benchmark hosts",
                "not measured (no --bench-cs given; `make bench` builds and passes it)",
                "",
            )
        )
    lines = [
        f"# feeddrive benchmark ({platform.node()}, {platform.machine()}, {os.cpu_count()} cores, "
        f"{time.strftime('%Y-%m-%d %H:%M')}, load average {os.getloadavg()[0]:.1f})",
        "",
        "| what | measured | target |",
        "|---|---|---|",
    ]
    lines += [f"| {a_} | {b} | {c} |" for a_, b, c in rows]
    text = "\n".join(lines) + "\n"
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
