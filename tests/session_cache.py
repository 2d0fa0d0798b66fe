"""Results computed once per test session and shared by the xdist workers: diagnoses and
simulated runs, which many tests make from the same inputs.

A result is stored as a pickle named by the SHA-256 of the pickled function name, its
arguments (the runs' arrays and metadata, the model file, every option) and the plant FMU
a ``Plant()`` loads (``$FEEDDRIVE_FMU``): any change of an input is a new key.  The file is
written under an exclusive ``fcntl`` lock of that key, so the worker that asks second
waits for the first and reads its result.  Each call returns a fresh unpickled copy: a
test that mutates what it gets cannot reach another test.  The directory is the
session's (``tmp_path_factory``'s base, shared by the workers), set by the
``_session_cache`` fixture of conftest.py; with none set, results are computed and not
kept.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import pickle
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from feeddrive.data import Run
from feeddrive.diagnose.workflow import Diagnosis
from feeddrive.diagnose.workflow import diagnose as _diagnose
from feeddrive.model_description import FMU_ENV
from feeddrive.model_file import ModelFile

T = TypeVar("T")

#: the environment variable naming the session's cache directory (inherited by nothing
#: outside the test process: set by conftest.py's fixture for the session only)
CACHE_ENV = "FEEDDRIVE_TEST_CACHE"


def cached(fn: Callable[..., T], *args: Any, **kwargs: Any) -> T:
    """``fn(*args, **kwargs)``, computed once per session for equal pickled arguments."""
    root = os.environ.get(CACHE_ENV)
    if not root:
        return fn(*args, **kwargs)
    fmu = os.environ.get(FMU_ENV)
    blob = pickle.dumps(
        (fn.__module__, fn.__qualname__, fmu, args, sorted(kwargs.items())), protocol=5
    )
    key = hashlib.sha256(blob).hexdigest()
    path = Path(root) / f"{fn.__name__}-{key}.pickle"
    with open(path.with_suffix(".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            if path.is_file():
                return pickle.loads(path.read_bytes())
            result = fn(*args, **kwargs)
            tmp = path.with_suffix(f".{os.getpid()}.tmp")
            tmp.write_bytes(pickle.dumps(result, protocol=5))
            os.replace(tmp, path)
            return pickle.loads(path.read_bytes())
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def diagnose(runs: list[Run], model: ModelFile, **kwargs: Any) -> Diagnosis:
    """feeddrive's ``diagnose(runs, model, **kwargs)``, once per session for equal inputs
    (a ``progress`` callback is called, so such a call is never cached)."""
    if kwargs.get("progress") is not None:
        return _diagnose(runs, model, **kwargs)
    return cached(_diagnose, list(runs), model, **kwargs)
