"""Build and run the C tests of the DP45 integrator (fmu_src/solvers/solver_dp45.c).

Two C programs under tests/c/: test_solver_dp45.c (accuracy against closed-form
solutions, step bookkeeping, error paths, cost) and test_solver_dp45_events.c
(event location, dense output). Each prints one line per check and
"N passed, M failed". Each is built twice: with the optimisation the FMU uses,
and with AddressSanitizer + UBSan (any memory error or undefined behaviour
aborts with a non-zero exit status).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "fmu_src" / "solvers"
SOLVER = SRC / "solver_dp45.c"
TEST_DIR = ROOT / "tests" / "c"
# program -> number of checks it makes (fewer means checks were lost)
PROGRAMS = {"test_solver_dp45": 28, "test_solver_dp45_events": 35}

FMU_FLAGS = ["-std=c99", "-O2", "-fPIC", "-Wall", "-Wextra", "-Werror"]
BUILDS = {
    "plain": ["-std=c99", "-Wall", "-Wextra", "-Werror", "-O2"],
    "sanitized": [
        "-std=c99",
        "-Wall",
        "-Wextra",
        "-Werror",
        "-O1",
        "-g",
        "-fsanitize=address,undefined",
        "-fno-sanitize-recover=all",
        "-fno-omit-frame-pointer",
    ],
}


def _compiler() -> str:
    cc = shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
    assert cc is not None, "no C compiler (cc/gcc/clang) on PATH: the FMU cannot be built either"
    return cc


def test_solver_compiles_with_fmu_flags(tmp_path: Path) -> None:
    """The solver object builds warning-free with exactly the FMU's flags."""
    proc = subprocess.run(
        [_compiler(), *FMU_FLAGS, "-c", str(SOLVER), "-o", str(tmp_path / "solver_dp45.o")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, f"{SOLVER}: compile failed:\n{proc.stderr}"


@pytest.mark.parametrize("build", sorted(BUILDS))
@pytest.mark.parametrize("program", sorted(PROGRAMS))
def test_solver_c_program(tmp_path: Path, program: str, build: str) -> None:
    """Every check of the C test program passes, also under ASan + UBSan."""
    test_c = TEST_DIR / f"{program}.c"
    exe = tmp_path / f"{program}_{build}"
    comp = subprocess.run(
        [
            _compiler(),
            *BUILDS[build],
            f"-I{SRC}",
            f"-I{TEST_DIR}",
            str(test_c),
            str(SOLVER),
            "-lm",
            "-o",
            str(exe),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert comp.returncode == 0, f"{test_c} ({build}): compile failed:\n{comp.stderr}"

    env = dict(os.environ)
    env["ASAN_OPTIONS"] = "abort_on_error=0:halt_on_error=1"
    env["UBSAN_OPTIONS"] = "halt_on_error=1:print_stacktrace=1"
    run = subprocess.run([str(exe)], capture_output=True, text=True, timeout=300, env=env)
    out = run.stdout + run.stderr
    failed = [line for line in run.stdout.splitlines() if line.startswith("FAIL")]
    assert not failed, f"{test_c} ({build}): failed checks:\n" + "\n".join(failed)
    assert run.returncode == 0, f"{test_c} ({build}): exit status {run.returncode}:\n{out}"

    summary = re.search(r"^(\d+) passed, (\d+) failed$", run.stdout, re.MULTILINE)
    assert summary is not None, f"{test_c} ({build}): no summary line in output:\n{out}"
    n_pass, n_fail = int(summary.group(1)), int(summary.group(2))
    assert n_fail == 0, f"{test_c} ({build}): {n_fail} checks failed"
    assert n_pass >= PROGRAMS[program], (
        f"{test_c} ({build}): only {n_pass} checks ran (expected {PROGRAMS[program]})"
    )
