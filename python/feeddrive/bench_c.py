"""Figures of the C benchmark hosts (test code in ``tests/c``, built by `make bench`).

``run_bench_cs(exe, library)`` runs ``bench_cs`` on the FMU's shared library and returns the
figures of the 30 mm / 6 s closed-loop sinusoid (2 kHz PID, 100 nm scale, one 0.5 ms
``fmi2DoStep`` per sample): real-time factor, friction events per simulated and per
wall-clock second, the wall time of one ``fmi2DoStep`` (median, 99th percentile, max) in µs, and
``wall_s_floor``: the loop's wall time with each 50-sample chunk at its fastest repetition (what a
loaded machine's preemptions do not touch).
``run_cycles(exe, library)`` runs ``cycles``: bytes one instance holds and memory growth over
many instantiate/simulate/free cycles.  ``run_two_fmus`` runs ``two_fmus``: the closed loop
as controller FMU + plant FMU stepped from C.  All take the paths of the built executables; nothing
here builds or locates them.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

#: samples of the bench_cs loop (6 s at 2 kHz)
BENCH_SAMPLES = 12_000


def _run(exe: Path, library: Path, *args: str) -> str:
    """Stdout of ``exe library args...``; one-line errors naming the missing file or the failure."""
    for need, what in (
        (exe, "C benchmark host (`make bench` builds it)"),
        (library, "FMU shared library"),
    ):
        if not Path(need).is_file():
            raise FileNotFoundError(f"{need}: no {what} there")
    p = subprocess.run([str(exe), str(library), *args], capture_output=True, text=True, check=False)
    if p.returncode != 0:
        raise RuntimeError(f"{exe} failed (exit {p.returncode}): {p.stderr.strip()}")
    return p.stdout


def run_bench_cs(
    exe: str | Path, library: str | Path, repetitions: int = 5, solver: str | None = None
) -> dict[str, float]:
    """Run the ``bench_cs`` host ``exe`` on ``library`` (the FMU's .so); its JSON figures as a dict.

    ``solver``: ``"fast"`` or ``"adaptive"`` sets ``solver.fast``; None keeps the FMU's default.
    """
    out = _run(Path(exe), Path(library), str(int(repetitions)), *([solver] if solver else []))
    return json.loads(out.strip().splitlines()[-1])


#: the groups of ``instructions_per_sample``: name -> the functions whose inclusive costs are summed
#: (``integrators``: the per-sample scheme's step and the adaptive DP45, no FMI glue around them;
#: ``loop``: the host's whole sample, the controller included)
IPS_GROUPS: dict[str, tuple[str, ...]] = {
    "fmi": ("fmi2DoStep", "fmi2GetReal", "fmi2SetReal"),
    "dostep": ("fmi2DoStep",),
    "get": ("fmi2GetReal",),
    "set": ("fmi2SetReal",),
    "integrators": ("fast_step", "dp45_advance"),
    "loop": ("cs_loop_step",),
}


def callgrind_groups(text: str, samples: int) -> dict[str, float]:
    """Instructions per sample of each of ``IPS_GROUPS`` from ``callgrind_annotate
    --inclusive=yes`` output ``text`` over ``samples`` samples (a function listed by several
    files counts once per line; a group with no function found is left out)."""
    cost: dict[str, int] = {}
    for m in re.finditer(r"^\s*([\d,]+) .*:(\w+) \[", text, re.M):
        cost[m.group(2)] = cost.get(m.group(2), 0) + int(m.group(1).replace(",", ""))
    return {
        g: sum(cost[f] for f in fns if f in cost) / samples
        for g, fns in IPS_GROUPS.items()
        if any(f in cost for f in fns)
    }


def instructions_per_sample(
    exe: str | Path, library: str | Path, solver: str
) -> dict[str, float] | None:
    """Instructions per sample of ``bench_cs`` under callgrind (repeatable, unlike wall time), by
    the groups of ``IPS_GROUPS`` (``fmi``: fmi2DoStep + fmi2GetReal + fmi2SetReal inclusive).
    One repetition of ``bench_cs`` runs the loop twice (timed whole, timed per step): 2 x 12 000
    samples. None when valgrind or callgrind_annotate is not installed."""
    if not (shutil.which("valgrind") and shutil.which("callgrind_annotate")):
        return None
    with tempfile.TemporaryDirectory() as d:
        out = Path(d) / "callgrind.out"
        subprocess.run(
            [
                "valgrind",
                "--tool=callgrind",
                f"--callgrind-out-file={out}",
                str(exe),
                str(library),
                "1",
                solver,
            ],
            capture_output=True,
            check=True,
        )
        text = subprocess.run(
            ["callgrind_annotate", "--inclusive=yes", str(out)],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
    groups = callgrind_groups(text, 2 * BENCH_SAMPLES)
    return groups if "fmi" in groups else None


def run_cycles(exe: str | Path, library: str | Path, cycles: int = 10_000) -> dict[str, int]:
    """Run the ``cycles`` host ``exe`` on ``library``.

    Returns
    -------
    dict with ``peak_bytes`` (held through the FMI callbacks at once) and ``rss_growth_kib``
    (resident memory growth over ``cycles`` instantiate/simulate/free cycles), where printed.
    """
    out = _run(Path(exe), Path(library), str(int(cycles)))
    fig = {}
    m = re.search(r"peak bytes held through the callbacks at once: (\d+)", out)
    if m:
        fig["peak_bytes"] = int(m.group(1))
    m = re.search(r"resident memory growth (-?\d+) KiB", out)
    if m:
        fig["rss_growth_kib"] = int(m.group(1))
    return fig


def markdown(fig: dict[str, float]) -> str:
    """The ``bench_cs`` figures as a markdown table."""
    rows = [
        ("CS real-time factor, 30 mm / 6 s closed loop from C", f"{fig['real_time_factor']:.0f}x"),
        ("friction state events per simulated second", f"{fig['state_events_per_sim_s']:.1f}"),
        ("friction state events per wall-clock second", f"{fig['state_events_per_wall_s']:.0f}"),
        (
            "all events (incl. current-loop samples) per wall-clock second",
            f"{fig['events_per_wall_s']:.3g}",
        ),
        ("fmi2DoStep of 0.5 ms, median", f"{fig['dostep_us_median']:.2f} µs"),
        ("fmi2DoStep of 0.5 ms, 99th percentile", f"{fig['dostep_us_p99']:.2f} µs"),
        ("fmi2DoStep of 0.5 ms, maximum", f"{fig['dostep_us_max']:.1f} µs"),
    ]
    return "| quantity | value |\n|---|---|\n" + "\n".join(f"| {a} | {b} |" for a, b in rows) + "\n"


def run_two_fmus(
    exe: str | Path,
    plant_library: str | Path,
    controller_library: str | Path,
    controller_values: dict[str, tuple[int, str, float]],
    n: int,
    x0: float,
    repetitions: int = 5,
) -> tuple[dict[str, float], list[float]]:
    """Run the ``two_fmus`` host (controller FMU + plant FMU stepped from C).

    ``controller_values``: name -> (value reference, "R"/"I"/"B", value).  Returns the JSON
    figures (``wall_s_best``, ``wall_s_median``) and x(t_k), k = 0..n.
    """
    if not Path(controller_library).is_file():
        raise FileNotFoundError(f"{controller_library}: no controller FMU shared library there")
    with tempfile.TemporaryDirectory() as d:
        params, out = Path(d) / "params.txt", Path(d) / "x.txt"
        params.write_text(
            "".join(f"{vr} {t} {float(v)!r}\n" for vr, t, v in controller_values.values())
        )
        text = _run(
            Path(exe),
            Path(plant_library),
            str(controller_library),
            str(params),
            str(int(n)),
            repr(float(x0)),
            str(out),
            str(int(repetitions)),
        )
        x = [float(v) for v in out.read_text().split()]
    return json.loads(text.strip().splitlines()[-1]), x
