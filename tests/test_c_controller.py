"""The controller FMU (DriveController, FMI 2.0 and 3.0) under the C test host tests/c/ctrl_host
(ctrl_host.c, ctrl_fuzz.c, ctrl_threads.c), built here with make: the controller's sources linked
in under AddressSanitizer + UBSan (``ctrl_host_san``) or ThreadSanitizer (``ctrl_host_tsan``), or
the shipped libraries as an importer loads them (``ctrl_host3``: DriveController.so through dlopen,
DriveController3.so linked for the FMI 3.0 calls).

* the hostile cases, one process each: a step of +-Inf/NaN, a step of 2e12 samples and one of 1e8
  samples at the smallest Ts are refused with the budget named (and change nothing), as is a
  step at a time whose double cannot tell the sample instants apart (t = 1e12 s, Ts = 0.5 ms);
  fmi3GetFloat64 with a NULL value-reference array, the Boolean calls (FMI 2.0 and 3.0) with
  nValueReferences = SIZE_MAX answer Error; the input clock refuses NULL arrays, a reference that is
  no clock, a set in Step Mode, Event Mode entered twice, a tick off the sample instants, a step
  past an untaken tick, and Event Mode on an instance made without it; an unstable state-space
  controller ends with an error naming the state that left the finite numbers and no getter
  answers OK with a non-finite value, and so does an unstable linear controller (``lti``),
  whose largest order with every element set runs clamped and refuses lti.n = 9 and a NaN
  element; reference parameters whose sample counts do not fit a long are refused (at the
  set: out of the declared range; at initialisation: the derived count, rule named);
* random FMI 2.0 and 3.0 calls and random settings (ctrl_fuzz.c's checks: valid status, a
  message with every non-OK answer, Error for every call illegal by its arguments, finite
  values from every getter that answers OK, no allocation left);
* 8 instances in threads give the runs of one at a time to the bit (no data race under TSan);
* a coverage-guided libFuzzer run (tests/c/ctrl_fuzz_lib.c: programs of FMI 2.0 and 3.0 calls,
  the same oracle) for 20 s from an empty corpus, when clang is installed.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from c_build import make_c

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "build" / "tests_c"
CTRL_SO = REPO / "build" / "controller" / "binaries" / "linux64" / "DriveController.so"
SAN_ENV = {
    "ASAN_OPTIONS": "detect_leaks=1:abort_on_error=1:halt_on_error=1",
    "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1",
}
SANITIZER_MARKS = (
    "runtime error:",
    "AddressSanitizer",
    "LeakSanitizer",
    "UndefinedBehaviorSanitizer",
    "ThreadSanitizer",
)
CASES = [
    "step_inf",
    "step_huge",
    "step_tiny_ts",
    "step_coarse_time",
    "get_float64_null",
    "boolean_size_max3",
    "clock",
    "boolean_size_max2",
    "unstable_state_space",
    "unstable_lti",
    "lti_full_order",
    "ref_duration",
    "ref_duration_samples",
    "ref_point_to_point",
    "ref_p2p_samples",
    "delay",
]


def build(*targets: str) -> None:
    make_c(*targets, jobs=2)


def run(prog: str, *args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    """Run a ctrl_host build; a run that does not end within ``timeout`` fails the test."""
    lib = str(CTRL_SO) if prog == "ctrl_host3" else "-"
    try:
        return subprocess.run(
            [str(OUT / prog), lib, *args],
            capture_output=True,
            text=True,
            timeout=timeout,
            env=dict(os.environ, **SAN_ENV),
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"{prog} {' '.join(args)} did not end within {timeout} s")


def assert_clean(p: subprocess.CompletedProcess) -> None:
    report = p.stdout[-3000:] + "\n" + p.stderr[-3000:]
    assert not any(m in p.stderr for m in SANITIZER_MARKS), report
    assert p.returncode == 0, report
    assert p.stdout.splitlines() and " 0 failed" in p.stdout.splitlines()[-1], report


@pytest.fixture(scope="module")
def san(fmu_path: Path) -> None:
    build("ctrl_host_san")


@pytest.mark.parametrize("case", CASES)
def test_hostile_case_sanitized(san, case: str) -> None:
    """Each case in its own process under ASan + UBSan: a hang, a crash or a sanitizer report fails it."""
    p = run("ctrl_host_san", "hostile", case, timeout=60)
    print(p.stdout)
    assert_clean(p)
    assert p.stdout.startswith(f"PASS {case}:"), p.stdout


def test_hostile_cases_shipped_libraries(fmu_path: Path) -> None:
    """Every case against the built DriveController.so and DriveController3.so."""
    build("ctrl_host3")
    for case in CASES:
        p = run("ctrl_host3", "hostile", case, timeout=60)
        assert_clean(p)


def _counts(stdout: str) -> dict[str, int]:
    """The fuzz run's counts by name (the numbers of its two summary lines)."""
    lines = stdout.splitlines()[-3:-1]
    text = " ".join(lines).replace("FMI 3.0", "")
    keys = [
        "calls",
        "fmi3",
        "illegal",
        "finite_gets",
        "values",
        "steps",
        "settings",
        "set_refused",
        "init_refused",
        "diverged",
        "samples",
        "ran",
    ]
    return dict(zip(keys, map(int, re.findall(r"\d+", text)), strict=True))


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_fuzz_sanitized(san, seed: int) -> None:
    """1 000 000 random FMI 2.0 / 3.0 calls per seed under ASan + UBSan."""
    p = run("ctrl_host_san", "fuzz", "1000000", str(seed))
    print("\n".join(p.stdout.splitlines()[-3:]))
    assert_clean(p)
    n = _counts(p.stdout)
    # deep enough to mean something: both versions, every kind of answer
    assert n["calls"] >= 1_000_000 and n["fmi3"] > 300_000, n
    assert n["illegal"] > 40_000 and n["finite_gets"] > 300_000 and n["steps"] > 300_000, n
    assert (
        n["settings"] > 8_000
        and n["init_refused"] > 500
        and n["diverged"] > 30
        and n["ran"] > 5_000
    ), n


def test_fuzz_shipped_libraries(fmu_path: Path) -> None:
    """The fuzz against the built DriveController.so and DriveController3.so."""
    build("ctrl_host3")
    p = run("ctrl_host3", "fuzz", "500000", "11")
    print("\n".join(p.stdout.splitlines()[-3:]))
    assert_clean(p)


def test_threads_sanitized(san) -> None:
    p = run("ctrl_host_san", "threads", "1", "8")
    print(p.stdout)
    assert_clean(p)
    assert p.stdout.count("PASS instance") == 8


def test_threads_thread_sanitizer(fmu_path: Path) -> None:
    """ThreadSanitizer: no data race between instances in 8 threads."""
    build("ctrl_host_tsan")
    p = run("ctrl_host_tsan", "threads", "0.5", "8")
    print(p.stdout)
    assert_clean(p)
    assert p.stdout.count("PASS instance") == 8


@pytest.mark.skipif(
    shutil.which(os.environ.get("CLANG", "clang")) is None,
    reason="clang (libFuzzer) is not installed: apt-get install clang (make test does as root)",
)
def test_libfuzzer_bounded_run(fmu_path: Path, tmp_path: Path) -> None:
    """20 s of coverage-guided programs of calls (seed 1) under ASan + UBSan: no finding."""
    build("ctrl_fuzz_lib")
    corpus = tmp_path / "corpus"
    corpus.mkdir()
    p = subprocess.run(
        [
            str(OUT / "ctrl_fuzz_lib"),
            "-seed=1",
            "-max_total_time=20",
            "-timeout=10",
            "-rss_limit_mb=2048",
            f"-artifact_prefix={tmp_path}/",
            str(corpus),
        ],
        capture_output=True,
        text=True,
        timeout=140,
    )
    report = p.stderr[-4000:]
    done = re.search(r"Done (\d+) runs in (\d+) second", p.stderr)
    assert p.returncode == 0 and done, report
    assert "ctrl_fuzz_lib finding" not in p.stderr and "ERROR:" not in p.stderr, report
    cov = re.findall(r"cov: (\d+)", p.stderr)
    print(
        f"{done.group(1)} executions in {done.group(2)} s, coverage {cov[-1] if cov else '?'} edges"
    )
    assert int(done.group(1)) > 1000
