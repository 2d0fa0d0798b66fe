"""Build the C test programs of tests/c into build/tests_c, one ``make`` at a time.

The xdist workers build the same programs (a sanitizer host, the fuzzers): two ``make``
runs that relink one binary at once leave the other worker executing a file still open for
writing ("Text file busy").  Every build goes through :func:`make_c`, which holds an
exclusive ``fcntl`` lock on build/tests_c/.make.lock while make runs: the second worker
waits, then finds the program up to date.
"""

from __future__ import annotations

import fcntl
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "build" / "tests_c"


def make_c(*targets: str, jobs: int = 1) -> subprocess.CompletedProcess:
    """``make -s -j<jobs> -C tests/c build/tests_c/<target>...`` under the build lock."""
    OUT.mkdir(parents=True, exist_ok=True)
    with open(OUT / ".make.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            return subprocess.run(
                ["make", "-s", f"-j{jobs}", "-C", str(REPO / "tests" / "c")]
                + [str(OUT / t) for t in targets],
                check=True,
                capture_output=True,
                text=True,
            )
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)
