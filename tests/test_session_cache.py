"""The session cache of the test suite (tests/session_cache.py): one computation per key,
a fresh copy per call, a new computation when an input changes."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from session_cache import CACHE_ENV, cached


def _logged(log: Path, a: np.ndarray, scale: float = 1.0) -> dict[str, np.ndarray]:
    """``a * scale``; each computation adds a line to ``log``."""
    with open(log, "a") as f:
        f.write(f"{scale}\n")
    return {"a": a * scale}


def test_one_computation_per_content_and_a_copy_per_call(tmp_path):
    assert os.environ.get(CACHE_ENV), "conftest.py's _session_cache fixture sets the directory"
    log = tmp_path / "computed.txt"  # a path of this test only: keys of this test only
    a = np.arange(5.0)
    first = cached(_logged, log, a, scale=2.0)
    second = cached(_logged, log, a.copy(), scale=2.0)  # equal content: the first's result
    assert np.array_equal(first["a"], 2 * a) and np.array_equal(second["a"], 2 * a)
    assert log.read_text().split() == ["2.0"]
    second["a"][0] = -1.0  # a mutation stays in the caller's copy
    assert cached(_logged, log, a, scale=2.0)["a"][0] == 0.0
    changed = a.copy()
    changed[-1] += 1e-12
    cached(_logged, log, changed, scale=2.0)  # other content: computed again
    cached(_logged, log, a, scale=3.0)  # another option: computed again
    assert log.read_text().split() == ["2.0", "2.0", "3.0"]
