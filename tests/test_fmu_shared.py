"""Plants of one FMU file share one extraction per process and stay independent instances."""

from __future__ import annotations

import gc
import os
import shutil
import subprocess
import sys
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from feeddrive.fmu import Plant, unpacked
from feeddrive.harness import make_controller, pid_spec, simulate_closed_loop, sinusoid

pytestmark = pytest.mark.usefixtures("fmu_path")  # on both FMI versions (conftest)


def _run(plant: Plant, ref) -> np.ndarray:
    return np.asarray(
        simulate_closed_loop(plant, make_controller(pid_spec(), ref), ref.n, float(ref.x[0]))["x"]
    )


def test_plants_share_one_extraction(fmu_path: Path) -> None:
    with Plant(path=fmu_path) as a, Plant(path=fmu_path, interface="me") as b:
        assert a._dir == b._dir == unpacked(fmu_path).directory
        assert a.md is b.md
        assert os.path.isdir(a._dir)
    assert os.path.isdir(unpacked(fmu_path).directory)  # kept for the next Plant


def test_instances_on_one_library_are_independent(fmu_path: Path) -> None:
    """Two live instances with different masses, stepped interleaved, give what each gives
    alone; closing one (fmpy's freeInstance unloads once) leaves the other running."""
    ref = sinusoid(0.010, 0.4, 0.150, 0.2)
    with Plant({"m": 16.1}, path=fmu_path) as p:
        alone_a = _run(p, ref)
    with Plant({"m": 30.0}, path=fmu_path) as p:
        alone_b = _run(p, ref)
    assert np.max(np.abs(alone_a - alone_b)) > 1e-7  # the mass matters at this speed
    a, b = Plant({"m": 16.1}, path=fmu_path), Plant({"m": 30.0}, path=fmu_path)
    a.start({"x": 0.14})
    b.start({"x": 0.14})
    a.close()  # dlclose of a's reference only
    both_b = _run(b, ref)
    b.close()
    np.testing.assert_array_equal(both_b, alone_b)
    unused = Plant(path=fmu_path)  # never started
    unused.close()
    with Plant({"m": 16.1}, path=fmu_path) as p:
        np.testing.assert_array_equal(_run(p, ref), alone_a)


def test_a_changed_file_is_extracted_again(fmu_path: Path, tmp_path: Path) -> None:
    copy = tmp_path / fmu_path.name
    shutil.copy2(fmu_path, copy)
    first = unpacked(copy).directory
    assert unpacked(copy).directory == first
    st = copy.stat()
    os.utime(copy, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000_000))
    second = unpacked(copy).directory
    assert second != first and os.path.isdir(first) and os.path.isdir(second)
    with Plant(path=copy) as p:
        assert p._dir == second


def test_extraction_removed_at_exit(fmu_path: Path) -> None:
    code = (
        "import sys; from feeddrive.fmu import Plant\n"
        f"p = Plant(path={str(fmu_path)!r}); p.start(); print(p._dir)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    directory = out.stdout.strip()
    assert directory and not os.path.exists(directory)


def test_a_started_plant_holds_under_64_kib(fmu_path: Path) -> None:
    """Ten started Plants (with their raw arrays) on a warm extraction: < 64 KiB of Python heap
    each (the FMI 3.0 ones share fmpy's function table of the library)."""
    with Plant(path=fmu_path) as warm:
        warm.start()
        warm.raw(["x"])
    gc.collect()
    tracemalloc.start()
    try:
        plants = [Plant(path=fmu_path, interface=itf) for itf in ("cs", "me") * 5]
        for p in plants:
            p.start({"x": 0.1})
            p.raw(["x", "v"])
        gc.collect()
        used = tracemalloc.get_traced_memory()[0]
    finally:
        tracemalloc.stop()
    for p in plants:
        p.close()
    assert used / len(plants) < 64 * 1024
