"""The FMU in a second importer: FMI4j (JNI, Maven Central info.laht.fmi4j:fmi-import 0.38.0) runs
it as co-simulation and as model exchange (tests/java: its own RK4 with 10 µs steps, time events
at the 0.5 ms samples, state events located by bisection to 1e-12 s) for the open-loop scenario
of tests/importer_scenario.py (u(t_k) = 0.5 sin(2 pi t_k) V, 2 s from rest at 150 mm). fmpy runs
the same input (CS; ME with CVode at 1e-9).

Tolerances:
* FMI4j CS against fmpy CS: the same binary doing the same fmi2DoStep calls; only the inputs
  differ, by the last bit of sin() (Java vs numpy): 1e-12 m, 1e-8 N.
* Any ME run against any other run: 0.1 µm in position and 0.05 N in friction force
  (measured: FMI4j ME vs fmpy CS 0.009 µm / 0.002 N, vs fmpy ME 0.04 µm / 0.004 N — CVode's
  1e-9 tolerance is the larger error).

Skipped when java or mvn is missing or `make importers` could not resolve FMI4j from Maven Central
(the reason it wrote); the test itself runs Maven offline.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from importer_scenario import SECONDS, TS, end_of_step_to_sampled
from importer_scenario import fmpy_runs as scenario_fmpy_runs
from importer_scenario import max_dev as _max_dev

REPO = Path(__file__).resolve().parents[1]
JAVA_DIR = REPO / "tests" / "java"
TARGET = REPO / "build" / "fmi4j-target"  # Maven's build directory (pom.xml)

CLASSPATH = TARGET / "classpath.txt"  # make importers: Maven resolved and compiled
SKIP = REPO / "build" / "importers" / "fmi4j.skip"  # make importers: why it could not


def _skip_reason() -> str | None:
    if shutil.which("java") is None or shutil.which("mvn") is None:
        return "FMI4j needs a JDK (java) and Maven (mvn); one is not installed"
    if not CLASSPATH.is_file():
        return (
            SKIP.read_text().strip()
            if SKIP.is_file()
            else "FMI4j is not installed: run `make importers`"
        )
    return None


pytestmark = pytest.mark.skipif(_skip_reason() is not None, reason=str(_skip_reason()))


def _maven_classpath() -> str:
    """tests/java compiled offline (its dependencies were resolved by `make importers`)."""
    p = subprocess.run(
        ["mvn", "-o", "-q", "-B", "compile"],
        cwd=JAVA_DIR,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert p.returncode == 0, (
        f"maven (offline) failed in {JAVA_DIR}:\n{p.stdout[-3000:]}\n{p.stderr[-3000:]}"
    )
    return str(TARGET / "classes") + ":" + CLASSPATH.read_text().strip()


@pytest.fixture(scope="module")
def fmi4j_runs(fmu_path: Path, tmp_path_factory) -> dict[str, np.ndarray]:
    out = tmp_path_factory.mktemp("fmi4j")
    p = subprocess.run(
        [
            "java",
            "-cp",
            _maven_classpath(),
            "feeddrive.fmi4j.Fmi4jRun",
            str(fmu_path),
            str(out),
            str(SECONDS),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    print(p.stdout)
    runs = {k: np.genfromtxt(out / f"{k}.csv", delimiter=",", names=True) for k in ("cs", "me")}
    # the Java host records every output at the end of each step (the left limit at t_k+1);
    # feeddrive.harness.simulate records the sampled current as Eq. 2's i[k] at row k: align it
    for d in runs.values():
        d["i"] = end_of_step_to_sampled(d["i"])
    return runs


@pytest.fixture(scope="module")
def fmpy_runs(fmu_path: Path) -> dict[str, dict[str, np.ndarray]]:
    return scenario_fmpy_runs(fmu_path)


def test_fmi4j_ran_the_scenario(fmi4j_runs):
    for k in ("cs", "me"):
        d = fmi4j_runs[k]
        assert len(d) == int(round(SECONDS / TS)) + 1
        assert np.all(np.isfinite(d["x"]))
        assert d["x"].max() - d["x"].min() > 0.03  # it moved: tens of millimetres


def test_fmi4j_cs_equals_fmpy_cs(fmi4j_runs, fmpy_runs):
    dev = _max_dev(fmi4j_runs["cs"], fmpy_runs["cs"])
    print("FMI4j CS vs fmpy CS:", dev)
    assert dev["x"] < 1e-12 and dev["F_friction"] < 1e-8 and dev["i"] < 1e-12


@pytest.mark.parametrize(
    "a,b",
    [
        (("fmi4j", "me"), ("fmpy", "cs")),
        (("fmi4j", "me"), ("fmpy", "me")),
        (("fmi4j", "cs"), ("fmpy", "me")),
    ],
)
def test_me_runs_agree(fmi4j_runs, fmpy_runs, a, b):
    src = {"fmi4j": fmi4j_runs, "fmpy": fmpy_runs}
    dev = _max_dev(src[a[0]][a[1]], src[b[0]][b[1]])
    print(f"{a} vs {b}:", dev)
    assert dev["x"] < 0.1e-6 and dev["F_friction"] < 0.05
