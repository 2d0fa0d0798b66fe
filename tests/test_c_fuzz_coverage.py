"""Coverage-guided fuzzing (libFuzzer, tests/c/fuzz_lib.c) of the FMU's state loader and of its
FMI call sequence under AddressSanitizer + UBSan, for a bounded time (2 x 20 s), from the seed
corpora in tests/c/corpus (new inputs go to a temporary folder, the repository's seeds are only
read). The target aborts on a sanitizer report, a getter answering fmi2OK with a non-finite
value, an error without a message or a callback allocation left after fmi2FreeInstance.

libFuzzer comes with clang: ``make test`` installs Debian's clang when it is missing and apt-get
is usable (as root); otherwise the fuzz run is skipped with that reason (the seed check runs).
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
CORPUS = REPO / "tests" / "c" / "corpus"
SECONDS = 20


def make(target: str) -> None:
    make_c(target)


def test_seed_corpus_is_current(fmu_path: Path, tmp_path: Path) -> None:
    """The committed seeds are what fuzz_seeds writes for this FMU (regenerate with
    build/tests_c/fuzz_seeds - tests/c/corpus after a change of the state format or the model)."""
    make("fuzz_seeds_san")
    for sub in ("state", "calls"):
        (tmp_path / sub).mkdir()
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1")
    subprocess.run(
        [str(OUT / "fuzz_seeds_san"), "-", str(tmp_path)], check=True, env=env, timeout=120
    )
    for sub in ("state", "calls"):
        fresh = {p.name: p.read_bytes() for p in (tmp_path / sub).iterdir()}
        kept = {p.name: p.read_bytes() for p in (CORPUS / sub).iterdir()}
        assert fresh == kept, f"tests/c/corpus/{sub} is stale: rerun fuzz_seeds"


@pytest.mark.skipif(
    shutil.which(os.environ.get("CLANG", "clang")) is None,
    reason="clang (libFuzzer) is not installed: apt-get install clang (make test does as root)",
)
@pytest.mark.parametrize("corpus", ["state", "calls"])
def test_libfuzzer_bounded_run(fmu_path: Path, tmp_path: Path, corpus: str) -> None:
    make("fuzz_lib")
    p = subprocess.run(
        [
            str(OUT / "fuzz_lib"),
            f"-max_total_time={SECONDS}",
            "-timeout=10",
            "-rss_limit_mb=2048",
            f"-artifact_prefix={tmp_path}/",
            str(tmp_path),
            str(CORPUS / corpus),
        ],
        capture_output=True,
        text=True,
        timeout=SECONDS + 120,
    )
    report = p.stderr[-4000:]
    done = re.search(r"Done (\d+) runs in (\d+) second", p.stderr)
    assert p.returncode == 0 and done, report
    assert "fuzz_lib finding" not in p.stderr and "ERROR:" not in p.stderr, report
    cov = re.findall(r"cov: (\d+)", p.stderr)
    print(
        f"{corpus}: {done.group(1)} executions in {done.group(2)} s, coverage {cov[-1] if cov else '?'} edges"
    )
    assert int(done.group(1)) > 1000
