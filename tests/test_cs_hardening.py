"""Hardening of the FMU's C code, driven by the C programs in tests/c (built here with make):

* fuzz of the FMI 2.0 API (random call sequences and values, NULL pointers, wrong value
  references, calls in the wrong state) with AddressSanitizer + UBSan: no crash, no sanitizer
  report, every illegal call answered fmi2Error/fmi2Discard with a message;
* 10 000 instantiate / initialise / simulate 10 ms / free cycles: every callback allocation
  freed, no growth of the anonymous resident memory, LeakSanitizer and valgrind clean;
* 8 instances in parallel threads give results bit-identical to one at a time (and
  ThreadSanitizer finds no data race);
* a one-hour simulated closed-loop run finishes and keeps its energy balance.

The sanitizer builds compile the FMU's sources into the test program (``*_san``); the plain
builds dlopen build/binaries/linux64/LinearMotorFeedDrive.so like an importer does.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

from c_build import make_c

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "build" / "tests_c"
SO = REPO / "build" / "binaries" / "linux64" / "LinearMotorFeedDrive.so"
SAN_ENV = {
    "ASAN_OPTIONS": "detect_leaks=1:abort_on_error=1:halt_on_error=1",
    "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1",
}
SANITIZER_MARKS = (
    "runtime error:",
    "AddressSanitizer",
    "LeakSanitizer",
    "UndefinedBehaviorSanitizer",
)


def build(*targets: str) -> None:
    """make -C tests/c the given driver binaries (plain: dlopen the .so; *_san: sanitizers)."""
    make_c(*targets, jobs=2)


def run(
    prog: str,
    *args: str,
    sanitized: bool = False,
    timeout: float = 600,
    wrapper: list[str] | None = None,
) -> subprocess.CompletedProcess:
    env = dict(os.environ, **SAN_ENV) if sanitized else None
    cmd = (wrapper or []) + [str(OUT / prog), "-" if sanitized else str(SO), *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)


def assert_clean(p: subprocess.CompletedProcess) -> None:
    report = p.stdout[-3000:] + "\n" + p.stderr[-3000:]
    assert not any(m in p.stderr for m in SANITIZER_MARKS), report
    assert p.returncode == 0, report
    assert " 0 failed" in p.stdout.splitlines()[-1], report


@pytest.fixture(scope="module")
def plain(fmu_path: Path) -> None:
    build("fuzz_fmi", "cycles", "threads", "hour_run")


@pytest.fixture(scope="module")
def sanitized(fmu_path: Path):
    """Builds the sanitizer drivers a test asks for (each compiles the FMU's sources: ~10 s)."""
    return build


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_fuzz_sanitized(sanitized, seed: int):
    """300 000 random calls per seed under ASan + UBSan."""
    sanitized("fuzz_fmi_san")
    p = run("fuzz_fmi_san", "300000", str(seed), sanitized=True)
    print(p.stdout.splitlines()[-2])
    assert_clean(p)
    # the run went deep enough to mean something
    summary = p.stdout.splitlines()[-2]
    assert int(summary.split(" illegal calls checked")[0].split(": ")[-1]) > 10000


def test_fuzz_plain_library(plain):
    """The same fuzz against the shared library as an importer loads it."""
    p = run("fuzz_fmi", "200000", "11")
    print(p.stdout.splitlines()[-2])
    assert_clean(p)


def test_cycles_plain(plain):
    """10 000 life cycles (ME and CS alternating): allocations balanced, no memory growth."""
    p = run("cycles", "10000")
    print(p.stdout)
    assert_clean(p)


def test_cycles_leak_sanitizer(sanitized):
    """10 000 life cycles under ASan/LSan (resident memory is ASan's quarantine there)."""
    sanitized("cycles_san")
    p = run("cycles_san", "10000", "--no-rss", sanitized=True)
    assert_clean(p)


@pytest.mark.skipif(shutil.which("valgrind") is None, reason="valgrind is not installed")
def test_cycles_valgrind(plain):
    """1 000 life cycles of the shared library under valgrind memcheck: no error, no leak."""
    p = run(
        "cycles",
        "1000",
        "--no-rss",
        wrapper=[
            "valgrind",
            "-q",
            "--leak-check=full",
            "--errors-for-leak-kinds=definite,indirect",
            "--error-exitcode=9",
        ],
    )
    assert_clean(p)


def test_threads_identical(plain):
    """8 instances with different closed loops (6 s each) in 8 threads == one at a time."""
    p = run("threads", "6", "8")
    print(p.stdout)
    assert_clean(p)
    assert p.stdout.count("PASS instance") == 8


def test_threads_sanitized(sanitized):
    sanitized("threads_san")
    p = run("threads_san", "1", "8", sanitized=True)
    assert_clean(p)


def test_threads_thread_sanitizer(fmu_path: Path):
    """The same 8 threads under ThreadSanitizer: no data race between instances."""
    build("threads_tsan")
    env = dict(os.environ, TSAN_OPTIONS="halt_on_error=1")
    p = subprocess.run(
        [str(OUT / "threads_tsan"), "-", "1", "8"],
        capture_output=True,
        text=True,
        timeout=600,
        env=env,
    )
    assert "ThreadSanitizer" not in p.stderr, p.stderr[-3000:]
    assert_clean(p)


def test_one_hour_run(plain):
    """3600 s of the 30 mm / 6 s closed loop: finishes, finite, tracking does not drift, the
    energy balance closes to 1e-5 of the motor's work (trapezoidal-rule error on 0.5 ms
    samples is ~1e-8 of it, measured), friction dissipates, nothing is logged."""
    p = run("hour_run", "3600", "1e-5", timeout=900)
    print(p.stdout)
    assert_clean(p)
    fig = json.loads(p.stdout.splitlines()[0])
    assert fig["simulated_s"] == 3600
    assert fig["state_events"] > 1000
