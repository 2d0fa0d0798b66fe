"""The C co-simulation benchmark runs and gives figures that make real-time use possible:
a 0.5 ms fmi2DoStep must fit in the 0.5 ms sample period with margin (99th percentile below
100 µs, a fifth of the period; measured ≈ 2 µs) and the loop runs at least 10x faster than real
time (measured ≈ 100x).  The host (tests/c/bench_cs) is test code, built here with make."""

from __future__ import annotations

from pathlib import Path

import pytest

from c_build import make_c
from feeddrive.bench_c import callgrind_groups, markdown, run_bench_cs

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "build" / "tests_c"
SO = REPO / "build" / "binaries" / "linux64" / "LinearMotorFeedDrive.so"


@pytest.fixture(scope="module")
def bench_cs(fmu_path: Path) -> Path:
    make_c("bench_cs")
    return OUT / "bench_cs"


def test_bench_cs_figures(bench_cs: Path):
    fig = run_bench_cs(bench_cs, SO, repetitions=2)
    print(markdown(fig))
    assert fig["simulated_s"] == 6
    assert fig["real_time_factor"] > 10
    assert fig["dostep_us_p99"] < 100
    assert fig["state_events"] > 0 and fig["dostep_calls"] == 2 * 12000
    assert fig["max_tracking_error_m"] < 50e-6
    # the floor sums each chunk's fastest repetition: never above the fastest whole run
    assert 0.0 < fig["wall_s_floor"] <= fig["wall_s_best"] * (1 + 1e-5)  # both printed to 6 digits


def test_bench_cs_missing_host_is_named(tmp_path: Path):
    with pytest.raises(FileNotFoundError, match="no C benchmark host"):
        run_bench_cs(tmp_path / "bench_cs", SO)


def test_callgrind_groups_per_sample():
    """The instruction groups of the bench table from callgrind_annotate's inclusive listing:
    each group's functions summed and divided by the samples; a group none of whose functions
    is listed is left out."""
    text = (
        "  2,400 (50.00%)  ???:fmi2DoStep [/b/LinearMotorFeedDrive.so]\n"
        "  1,200 (25.00%)  ???:fast_step [/b/LinearMotorFeedDrive.so]\n"
        "    240 ( 5.00%)  ???:dp45_advance [/b/LinearMotorFeedDrive.so]\n"
        "    480 (10.00%)  ???:fmi2GetReal [/b/LinearMotorFeedDrive.so]\n"
        "    120 ( 2.50%)  ???:fmi2SetReal [/b/LinearMotorFeedDrive.so]\n"
        "  3,600 (75.00%)  tests/c/cs_loop.c:cs_loop_step [/b/bench_cs]\n"
        "  9,999 (99.00%)  ./stdlib/msort.c:msort_with_tmp.part.0'2 [/lib/libc.so.6]\n"
    )
    g = callgrind_groups(text, 120)
    assert g == {
        "fmi": 25.0,
        "dostep": 20.0,
        "get": 4.0,
        "set": 1.0,
        "integrators": 12.0,
        "loop": 30.0,
    }
    assert callgrind_groups("  100 (1.00%)  ???:main [/b/bench_cs]\n", 10) == {}
