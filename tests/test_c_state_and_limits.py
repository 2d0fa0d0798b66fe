"""Saved states and accepted limits, C side, driven by the C programs tests/c/state_flip.c and tests/c/limits.c under
AddressSanitizer + UBSan (the FMU's sources compiled into the test program):

* every single-bit flip of a serialised co-simulation and model-exchange state (raw, and with the
  payload's CRC-32 recomputed so that every field check is reached) and every truncation is
  refused with a message or loads into a state that runs clean; states of the other interface,
  of another GUID or structure are refused naming what differs; a round trip is bit-identical;
* every parameter and input at and beyond both ends of its declared [min, max]: beyond is refused,
  at the end every output stays finite (or the call is refused with a message);
* the work budget: friction.C = 1e9 is refused naming friction.C, a 100 s step at rest works, an
  ME time jump of 1e7 s is refused; startTime 1.7e9 s and 1e10 s give the samples of startTime 0;
* fmi2GetDerivatives after a failed fmi2EnterEventMode is not fmi2OK; Integer counters saturate.
"""

from __future__ import annotations

import json
import os
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


def run(prog: str, sanitized: bool = True) -> tuple[subprocess.CompletedProcess, list[dict]]:
    make_c(prog)
    env = dict(os.environ, **SAN_ENV) if sanitized else None
    p = subprocess.run(
        [str(OUT / prog), "-" if sanitized else str(SO)],
        capture_output=True,
        text=True,
        timeout=600,
        env=env,
    )
    report = p.stdout[-4000:] + "\n" + p.stderr[-4000:]
    assert not any(m in p.stderr for m in SANITIZER_MARKS), report
    assert p.returncode == 0 and " 0 failed" in p.stdout.splitlines()[-1], report
    return p, [json.loads(line) for line in p.stdout.splitlines() if line.startswith("{")]


def test_corrupted_states_refused_or_clean(fmu_path: Path) -> None:
    _p, figs = run("state_flip_san")
    print("\n".join(json.dumps(f) for f in figs))
    assert [f["interface"] for f in figs] == ["co-simulation", "model exchange"]
    for f in figs:
        assert f["flips_refused"] + f["flips_accepted_clean"] == f["bit_flips"] == 8 * f["bytes"]
        # without a forged checksum no single flip gets through (CRC-32 detects every 1-bit error)
        assert f["flips_accepted_clean"] == 0
        assert f["forged_refused"] > 1000 and f["forged_accepted_clean"] > 1000
        assert f["truncations_refused"] == f["truncations"] == f["bytes"] + 1


def test_limits_budget_and_time(fmu_path: Path) -> None:
    _p, figs = run("limits_san")
    print("\n".join(json.dumps(f) for f in figs))
    by = {k: v for f in figs for k, v in f.items() if k != "start_time"}
    r = by["ranges"]
    assert r["variables"] >= 100 and r["beyond_refused"] == r["values"] // 2
    assert r["runs_clean"] + r["runs_refused_with_message"] == r["at_end_accepted"]
    assert "friction.C = 1000000000" in by["budget_friction_C_1e9"]["message"]
    assert by["budget_friction_C_1e9"]["wall_s"] < 20.0
    assert by["long_step_at_rest"]["status"] == 0
    starts = [f for f in figs if "start_time" in f]
    assert [f["start_time"] for f in starts] == [1.7e9, 1e10]
    assert all(f["samples_in_2s"] == 4000 and f["currents_identical"] for f in starts)


@pytest.mark.parametrize("prog", ["limits"])
def test_limits_shared_library(fmu_path: Path, prog: str) -> None:
    """The same limits against the shipped .so as an importer loads it."""
    run(prog, sanitized=False)
