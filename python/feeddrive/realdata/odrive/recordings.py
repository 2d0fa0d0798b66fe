"""The ODrive data set: its folders and map names, the measured holding-current maps and the
slow runs, loaded and checked."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...inputs import open_input

COUNTS_PER_REV = 8192
MAP_FOLDER = "coggingmap_0"
SLOW_FOLDERS = ("slow2", "slow2_slower")
REFERENCE_MAP = "a_16"  # forward map whose lines the README quotes
ISOLATED_MAP = "iso_16"  # forward map with the neighbouring motor moved away
REPEAT_TRIALS = ("b_16", "d_16", "c_16")
FORWARD_16 = ("a_16", "b_16", "c_16", "d_16")
REVERSE_16 = ("e_16r", "rev_16")

_MAP_NAME = re.compile(
    r"^cogging_measure_final_(?P<trial>[a-z]+)_(?P<step>\d+)(?P<r>r?)(?P<interp>_interp)?\.npy$"
)


@dataclass(frozen=True)
class CoggingMap:
    """One measured holding-current map: Iq [A] at the measured encoder counts."""

    name: str
    step: int
    reverse: bool
    counts: np.ndarray
    current: np.ndarray


@dataclass(frozen=True)
class SlowRun:
    """One slow velocity-controlled run, sampled at non-uniform times."""

    name: str
    time: np.ndarray
    position: np.ndarray
    current: np.ndarray


def map_grid(step: int, reverse: bool) -> np.ndarray:
    """Encoder counts measured by a sweep with ``step``; a reverse sweep visits 8191, 8191-step, ..."""
    if step <= 0 or COUNTS_PER_REV % step:
        raise ValueError(f"step {step} does not divide {COUNTS_PER_REV} counts")
    first = (COUNTS_PER_REV - 1) % step if reverse else 0
    return np.arange(first, COUNTS_PER_REV, step)


def _load_npy(path: Path) -> np.ndarray:
    """The array of a ``.npy`` regular file (a FIFO or a device is refused, see
    :func:`feeddrive.inputs.open_input`); ValueError naming the file when it is no array."""
    with open_input(path, encoding=None) as f:
        try:
            data = np.load(f, allow_pickle=False)
        except EOFError:
            raise ValueError(f"{path}: empty or cut short: not a .npy array") from None
    if not isinstance(data, np.ndarray):
        raise ValueError(f"{path}: not a .npy array")
    return data


def load_map(path: str | Path) -> CoggingMap:
    """Load ``cogging_measure_final_<trial>_<step>[r].npy``; keep only the measured entries."""
    path = Path(path)
    m = _MAP_NAME.match(path.name)
    if m is None:
        raise ValueError(f"{path}: name is not cogging_measure_final_<trial>_<step>[r].npy")
    if m["interp"]:
        raise ValueError(f"{path}: an interpolated (filled-in) map, not a measurement")
    data = _load_npy(path)
    if data.shape != (COUNTS_PER_REV,) or data.dtype.kind != "f":
        raise ValueError(
            f"{path}: expected float array of shape ({COUNTS_PER_REV},), "
            f"got {data.dtype} {data.shape}"
        )
    if (bad := np.flatnonzero(~np.isfinite(data))).size:
        raise ValueError(f"{path}: non-finite current at count {bad[0]}")
    step, reverse = int(m["step"]), bool(m["r"]) or m["trial"] == "rev"
    grid = map_grid(step, reverse)
    stray = np.flatnonzero(np.isin(np.arange(COUNTS_PER_REV), grid, invert=True) & (data != 0))
    if stray.size:
        raise ValueError(
            f"{path}: {stray.size} non-zero entries off the {step}-count grid "
            f"(first at count {stray[0]}); the step in the name does not fit"
        )
    unmeasured = np.flatnonzero(data[grid] == 0)
    if unmeasured.size > grid.size // 100:
        raise ValueError(
            f"{path}: {unmeasured.size} of {grid.size} grid entries are 0 "
            f"(first at count {grid[unmeasured[0]]}): sweep incomplete"
        )
    name = path.name.removeprefix("cogging_measure_final_").removesuffix(".npy")
    return CoggingMap(name, step, reverse, grid, data[grid].copy())


def load_maps(folder: str | Path) -> dict[str, CoggingMap]:
    """All measured maps (``*_interp`` skipped) in ``folder/coggingmap_0``, keyed by e.g. ``a_16``."""
    d = Path(folder) / MAP_FOLDER
    if not d.is_dir():
        raise FileNotFoundError(f"{d}: cogging-map folder not found")
    maps = [
        load_map(p)
        for p in sorted(d.glob("cogging_measure_final_*.npy"))
        if not p.name.endswith("_interp.npy")
    ]
    return {m.name: m for m in maps}


def load_slow_run(path: str | Path) -> SlowRun:
    """Load a slow run: float array (3, N), rows time [s], position [counts], Iq [A]."""
    path = Path(path)
    data = _load_npy(path)
    if data.ndim != 2 or data.shape[0] != 3 or data.shape[1] < 100 or data.dtype.kind != "f":
        raise ValueError(
            f"{path}: expected float array of shape (3, N>=100), got {data.dtype} {data.shape}"
        )
    for row, what in enumerate(("time", "position", "current")):
        if (bad := np.flatnonzero(~np.isfinite(data[row]))).size:
            raise ValueError(f"{path}: non-finite {what} at sample {bad[0]}")
    if (back := np.flatnonzero(np.diff(data[0]) <= 0)).size:
        raise ValueError(f"{path}: time not increasing at sample {back[0] + 1}")
    return SlowRun(f"{path.parent.name}/{path.stem}", *(data[i].copy() for i in range(3)))
