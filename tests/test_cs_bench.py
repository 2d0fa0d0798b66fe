"""The C co-simulation benchmark runs and gives figures that make real-time use possible:
a 0.5 ms fmi2DoStep must fit in the 0.5 ms sample period with margin (99th percentile below
100 µs, a fifth of the period; measured ≈ 2 µs) and the loop runs at least 10x faster than real
time (measured ≈ 100x)."""
from __future__ import annotations

from pathlib import Path

from feeddrive.bench_c import markdown, run_bench_cs


def test_bench_cs_figures(fmu_path: Path):
    fig = run_bench_cs(repetitions=2)
    print(markdown(fig))
    assert fig["simulated_s"] == 6
    assert fig["real_time_factor"] > 10
    assert fig["dostep_us_p99"] < 100
    assert fig["state_events"] > 0 and fig["dostep_calls"] == 2 * 12000
    assert fig["max_tracking_error_m"] < 50e-6
