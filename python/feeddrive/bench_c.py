"""Co-simulation benchmark from C: builds and runs tests/c/bench_cs on the FMU's shared library.

``run_bench_cs()`` returns the figures of the 30 mm / 6 s closed-loop sinusoid (2 kHz PID, 100 nm
scale, one 0.5 ms ``fmi2DoStep`` per sample): real-time factor, friction events per simulated and
per wall-clock second, and the wall time of one ``fmi2DoStep`` (median, 99th percentile, max) in µs.
"""
from __future__ import annotations

import json
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
BENCH = REPO / "build" / "tests_c" / "bench_cs"
SO = REPO / "build" / "binaries" / "linux64" / "LinearMotorFeedDrive.so"


def run_bench_cs(repetitions: int = 5) -> dict[str, float]:
    """Build ``bench_cs`` (needs ``make fmu`` first) and run it; the JSON figures as a dict."""
    if not SO.is_file():
        raise FileNotFoundError(f"{SO}: no FMU library; build it with `make fmu`")
    subprocess.run(["make", "-s", "-C", str(REPO / "tests" / "c"), str(BENCH)], check=True,
                   capture_output=True, text=True)
    p = subprocess.run([str(BENCH), str(SO), str(int(repetitions))], capture_output=True, text=True,
                       check=False)
    if p.returncode != 0:
        raise RuntimeError(f"{BENCH} failed (exit {p.returncode}): {p.stderr.strip()}")
    return json.loads(p.stdout.strip().splitlines()[-1])


def markdown(fig: dict[str, float]) -> str:
    """The figures as a markdown table."""
    rows = [("CS real-time factor, 30 mm / 6 s closed loop from C", f"{fig['real_time_factor']:.0f}x"),
            ("friction state events per simulated second", f"{fig['state_events_per_sim_s']:.1f}"),
            ("friction state events per wall-clock second", f"{fig['state_events_per_wall_s']:.0f}"),
            ("all events (incl. current-loop samples) per wall-clock second",
             f"{fig['events_per_wall_s']:.3g}"),
            ("fmi2DoStep of 0.5 ms, median", f"{fig['dostep_us_median']:.2f} µs"),
            ("fmi2DoStep of 0.5 ms, 99th percentile", f"{fig['dostep_us_p99']:.2f} µs"),
            ("fmi2DoStep of 0.5 ms, maximum", f"{fig['dostep_us_max']:.1f} µs")]
    return "| quantity | value |\n|---|---|\n" + "\n".join(f"| {a} | {b} |" for a, b in rows) + "\n"


if __name__ == "__main__":
    print(markdown(run_bench_cs()))
