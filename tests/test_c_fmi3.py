"""At the C level: the FMI 3.0 glue (fmu_src/fmi3_*.c) driven by the C host
tests/c/fmi3_host.c (+ fmi3_host_robust.c) under AddressSanitizer + UBSan + LeakSanitizer, the FMU's FMI 3.0 sources
(those of the FMI 3.0 .so, the FMI 2.0 glue with them) compiled into the program:

* instantiation for model exchange and co-simulation (eventModeUsed and earlyReturnAllowed both
  ways; a wrong token and required intermediate variables refused);
* Configuration Mode: friction.N = 1, 5, 10 gives MODEL_NX - 10 + N states, arrays of dimension N
  are got and set with N values (N + 1 refused naming friction.N), N = 0 and 11 refused;
* a model-exchange loop (forward Euler, h = 10 us, event indicators, fmi3UpdateDiscreteStates at
  sign changes and at the current-loop samples, time events) that lands on the co-simulation;
* 1 s of co-simulation of u = 1.5 V sin(2 pi 2 Hz t), 1 ms steps, in the four event-mode /
  early-return combinations: every position identical (0 m) to the FMI 2.0 co-simulation;
* the FMU state (get, set, serialise, deserialise into the same and a fresh instance) continues
  bit-identically; every flipped byte and every truncation of a serialised state is refused; a
  state of friction.N = 5 into an instance at N = 9, a state saved in Event Mode into an instance
  made with eventModeUsed = false, and states with x = -2000 m or v = 1e300 m/s (CRC recomputed)
  are refused naming what differs;
* NaN and beyond-[min, max] values of every Float64 parameter and input refused naming it;
* calls in wrong states refused naming the call; 900 instances created and freed, no leak, also
  when their FMU states are left to fmi3FreeInstance.
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
PROG = "fmi3_host_san"


def run(*args: str) -> subprocess.CompletedProcess:
    make_c(PROG)
    return subprocess.run(
        [str(OUT / PROG), *args],
        capture_output=True,
        text=True,
        timeout=300,
        env=dict(os.environ, **SAN_ENV),
    )


@pytest.fixture(scope="module")
def figures(fmu3_path: Path) -> dict[str, list[dict]]:
    p = run()
    report = p.stdout[-4000:] + "\n" + p.stderr[-4000:]
    assert not any(m in p.stderr for m in SANITIZER_MARKS), report
    assert p.returncode == 0 and p.stdout.splitlines()[-1].endswith(" 0 failed"), report
    print(p.stdout)
    out: dict[str, list[dict]] = {}
    for line in p.stdout.splitlines():
        if line.startswith("{"):
            for k, v in json.loads(line).items():
                out.setdefault(k, []).append(v)
    return out


def test_instantiation_and_configuration(figures: dict[str, list[dict]]) -> None:
    inst = figures["instantiate"][0]
    assert inst["instances"] == 5 and inst["wrong_token_refused"] and inst["intermediate_refused"]
    assert figures["configuration"][0]["N_out_of_range_refused"] == [0, 11]
    me = figures["me"]
    assert [r["N"] for r in me] == [1, 5, 10]
    # the states: x, v, the others of MODEL_NX, and N friction elements (not 10)
    assert [r["nx"] - r["N"] for r in me] == [me[0]["nx"] - 1] * 3


def test_model_exchange_loop(figures: dict[str, list[dict]]) -> None:
    for r in figures["me"]:
        # a time event at every current-loop sample (Ts = 0.5 ms) over 0.25 s
        assert r["time_events"] == 500
        assert r["state_events"] >= 3  # the friction switches of u's first half period
        assert r["updates"] >= r["time_events"] + r["state_events"]
    n5 = figures["me"][1]
    # forward Euler is first order: 0.8 um from the co-simulation's DP45 at h = 10 us (0.6 um
    # between h = 10 us and 2 us); 5 um is ~6x that, against 74 mm travelled
    assert abs(n5["x_end"] - n5["cs_x_at_0.25s"]) < 5e-6
    assert n5["cs_x_at_0.25s"] - 0.15 > 0.07
    off = figures["me_no_current_dynamics"][0]
    assert off["time_events"] == 0 and off["state_events"] >= 1


def test_co_simulation_equals_fmi2(figures: dict[str, list[dict]]) -> None:
    cs = figures["cs"]
    assert [(r["event_mode"], r["early_return"]) for r in cs] == [(0, 0), (0, 1), (1, 0), (1, 1)]
    for r in cs:
        assert r["max_abs_dx_vs_fmi2_m"] == 0.0 and r["x_end"] == r["fmi2_x_end"]
        assert r["x_range_m"] > 0.05  # the stage moves (u's 2 Hz swings), switches happen
    plain, early, events, both = cs
    assert plain["early_returns"] == 0 and plain["events"] == 0 and plain["dosteps"] == 1000
    # one extra fmi3DoStep per early return; every switch ends a step early
    assert early["early_returns"] >= 10 and early["dosteps"] == 1000 + early["early_returns"]
    assert events["events"] >= 10 and events["early_returns"] == 0
    assert both["early_returns"] == early["early_returns"] == both["events"]


def test_fmu_state(figures: dict[str, list[dict]]) -> None:
    s = figures["state"][0]
    assert s["bit_identical"] and s["continued_steps"] == 300
    assert s["byte_flips"] == s["flips_refused"] == s["bytes"] > 1000
    assert s["truncations"] == s["truncations_refused"] == s["bytes"]


def test_state_structure_and_ranges(figures: dict[str, list[dict]]) -> None:
    assert figures["state_structure"][0]["refused"] == 4


def test_limits_and_wrong_states(figures: dict[str, list[dict]]) -> None:
    lim = figures["limits"][0]
    assert lim["variables"] >= 100 and lim["nan_refused"] == lim["variables"]
    assert lim["beyond_refused"] >= 2 * lim["variables"] - 5  # both ends where both are finite
    assert figures["wrong_states"][0]["refused"] == 15
    assert figures["many"][0] == {"instances": 900, "alive_at_once": 300}


def test_free_instance_frees_its_states(fmu3_path: Path) -> None:
    """FMU states never given to fmi3FreeFMUState are freed by fmi3FreeInstance (FMI 3.0: it
    frees all memory the FMU's functions allocated); before, LeakSanitizer found 90 x 4 KB."""
    p = run("--leave-states")
    assert not any(m in p.stderr for m in SANITIZER_MARKS), p.stderr[-2000:]
    assert p.returncode == 0 and p.stdout.splitlines()[-1].endswith(" 0 failed"), p.stdout[-2000:]
