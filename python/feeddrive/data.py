"""Measured-data runs: the loader and writer of the recording format (``docs/data-format.md``).

A run is one CSV file with a header row (columns ``time, u, i, x, x_ref, F_load`` in SI,
``time``, ``u``, ``x`` required; any other column is kept as it is) plus an optional JSON
sidecar with the same stem (``run.csv`` + ``run.json``) that says how the experiment was run
(the runs our commands write use one schema for it: :mod:`feeddrive.harness.sidecar`).  A
recording may be gzip-compressed (``run.csv.gz`` + ``run.json``): it is read as a stream, with
the same rules, and :func:`write_run` compresses when the file name ends in ``.gz``.

The loader is strict: every rule of the recording format that a file breaks raises :class:`DataError`
naming the file, the 1-based line (the header is line 1) and the column.  Rows are never
dropped or reordered.  A run and its sidecar must be regular files (a FIFO or a device is
refused before it is read); the header row must end within :data:`MAX_HEADER_BYTES`; a number
is plain ASCII decimal with an optional exponent (``-1.5e-3``; ``nan``/``inf`` are read and
then refused as non-finite), never what Python's ``float`` also takes (``0.1_2``, digits of
other scripts).  The writer refuses a run the loader would reject and writes floats
with ``repr`` (the shortest string that round-trips a float64 exactly).  The reading of the
CSV text (chunks, number syntax, header and value checks) is :mod:`feeddrive.data_csv`.
"""

from __future__ import annotations

import csv
import gzip
import io
import json
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .data_csv import (
    KNOWN_COLUMNS,
    MAX_HEADER_BYTES,
    MAX_LINE_CHARS,
    REQUIRED_COLUMNS,
    RUN_SUFFIXES,
    DataError,
    _check_values,
    is_compressed,
    read_columns,
    run_stem,
)
from .inputs import InputFileError, read_text

__all__ = [
    "KNOWN_COLUMNS",
    "MAX_ABS",
    "MAX_HEADER_BYTES",
    "MAX_LINE_CHARS",
    "MIN_ROWS",
    "RECORDING_DECIMALS",
    "REQUIRED_COLUMNS",
    "RUN_SUFFIXES",
    "SAMPLE_JITTER",
    "SAMPLE_STEP_RANGE",
    "DataError",
    "Run",
    "fixed_text",
    "time_text",
    "check_plausible",
    "check_sampling",
    "load_run",
    "load_runs",
    "run_files",
    "run_stem",
    "sidecar_path",
    "write_run",
]

_OPTIONAL_COLUMNS = tuple(c for c in KNOWN_COLUMNS if c not in REQUIRED_COLUMNS)


@dataclass
class Run:
    """One experiment: sampled signals in SI, the sidecar metadata and unknown columns.

    ``time``, ``u``, ``x`` are required; ``i``, ``x_ref``, ``F_load`` are ``None`` when the
    file has no such column.  ``extra`` keeps every other column (float arrays, or string
    arrays for non-numeric ones) in file order.  ``meta`` is the sidecar JSON ({} if none).
    """

    time: np.ndarray
    u: np.ndarray
    x: np.ndarray
    i: np.ndarray | None = None
    x_ref: np.ndarray | None = None
    F_load: np.ndarray | None = None
    meta: dict = field(default_factory=dict)
    extra: dict[str, np.ndarray] = field(default_factory=dict)
    path: Path | None = None

    def __post_init__(self) -> None:
        for name in KNOWN_COLUMNS:
            value = getattr(self, name)
            if value is None:
                if name in REQUIRED_COLUMNS:
                    raise ValueError(f"Run: column {name!r} is required")
                continue
            arr = np.asarray(value, dtype=float)
            if arr.ndim != 1:
                raise ValueError(f"Run: column {name!r} must be 1-D, got shape {arr.shape}")
            setattr(self, name, arr)
        self.extra = {str(k): np.asarray(v) for k, v in self.extra.items()}
        for k, v in self.extra.items():
            if k in KNOWN_COLUMNS:
                raise ValueError(
                    f"Run: extra column {k!r} clashes with a column of the recording format"
                )
            if v.ndim != 1:
                raise ValueError(f"Run: extra column {k!r} must be 1-D, got shape {v.shape}")
        n = len(self.time)
        for name, arr in self.columns().items():
            if len(arr) != n:
                raise ValueError(f"Run: column {name!r} has {len(arr)} samples, time has {n}")
        if self.path is not None:
            self.path = Path(self.path)

    def columns(self) -> dict[str, np.ndarray]:
        """Every present column, the format's columns first (in the format's order), then ``extra``."""
        cols = {c: getattr(self, c) for c in KNOWN_COLUMNS if getattr(self, c) is not None}
        cols.update(self.extra)
        return cols

    @property
    def n(self) -> int:
        """Number of rows (samples)."""
        return len(self.time)

    @property
    def Ts(self) -> float:
        """Median sample interval [s]."""
        return float(np.median(np.diff(self.time)))

    @property
    def has_current(self) -> bool:
        """True when the measured current ``i`` is present (else tools use G(1)*u)."""
        return self.i is not None

    @property
    def name(self) -> str:
        """The file's stem (without ``.csv`` / ``.csv.gz``), or ``meta['name']`` / "" for a run
        not read from a file."""
        if self.path is not None:
            return run_stem(self.path)
        return str(self.meta.get("name", ""))


def sidecar_path(path: str | Path) -> Path:
    """The JSON sidecar that belongs to a run CSV (same stem, ``.json``: ``run.csv`` and
    ``run.csv.gz`` both have ``run.json``)."""
    path = Path(path)
    return path.with_name(run_stem(path) + ".json")


def _no_constant(path: Path):
    """json ``parse_constant`` hook: NaN and Infinity are not JSON (RFC 8259)."""

    def hook(name: str) -> Any:
        raise DataError(path, None, None, f"{name} is not a JSON number (non-finite value)")

    return hook


def _load_sidecar(csv_path: Path) -> dict:
    jpath = sidecar_path(csv_path)
    if not os.path.lexists(jpath):
        return {}
    try:
        text = read_text(jpath)
    except InputFileError as e:
        raise DataError(jpath, None, None, e.problem) from None
    except (OSError, UnicodeDecodeError) as e:
        raise DataError(jpath, None, None, f"unreadable sidecar JSON: {e}") from None
    try:
        meta = json.loads(text, parse_constant=_no_constant(jpath))
    except json.JSONDecodeError as e:
        raise DataError(
            jpath, e.lineno, None, f"invalid sidecar JSON at column {e.colno}: {e.msg}"
        ) from None
    except RecursionError:
        raise DataError(jpath, None, None, "sidecar JSON nested too deeply") from None
    if not isinstance(meta, dict):
        raise DataError(
            jpath, 1, None, f"sidecar JSON must be an object, got {type(meta).__name__}"
        )
    return meta


def load_run(path: str | Path) -> Run:
    """Read one recording (CSV plus its optional JSON sidecar).

    Parameters
    ----------
    path : str or Path
        The CSV file (``.csv``, or gzip-compressed ``.csv.gz``).

    Returns
    -------
    Run
        Columns as float64 arrays; unknown columns in ``extra`` (float when every cell is a
        number, else str); ``meta`` from the sidecar or {}.

    Raises
    ------
    DataError
        For every broken rule of the recording format (missing required column, duplicate column name,
        row with the wrong number of fields, non-numeric or non-finite value in a known
        column, time not strictly increasing, fewer than 2 rows, invalid sidecar JSON),
        naming the file, line and column.
    """
    path = Path(path)
    cols, extra, lines = read_columns(path)
    _check_values(path, cols, lines)
    meta = _load_sidecar(path)
    return Run(**cols, meta=meta, extra=extra, path=path)


#: plausible median sample step [s] (0.1 us .. 1 s: time in seconds, not ms or us)
SAMPLE_STEP_RANGE: tuple[float, float] = (1e-7, 1.0)
#: largest deviation of one sample step from the median step (fraction)
SAMPLE_JITTER = 0.10


def check_sampling(run: Run) -> float:
    """The run's median sample step [s], after checking that the sampling is plausible.

    Raises :class:`DataError` (file, line, column ``time``) when the median step is outside
    :data:`SAMPLE_STEP_RANGE` (e.g. time in ms) or one step differs from it by more than
    :data:`SAMPLE_JITTER` (gaps, jitter: the tools assume uniform sampling).
    """
    dt = np.diff(run.time)
    path = run.path if run.path is not None else Path(run.name or "run")
    if dt.size == 0:
        raise DataError(path, None, "time", "fewer than 2 samples")
    Ts = float(np.median(dt))
    lo, hi = SAMPLE_STEP_RANGE
    if not lo <= Ts <= hi:
        raise DataError(
            path,
            None,
            "time",
            f"median sample step {Ts:g} s is outside {lo:g} .. {hi:g} s (time must be in seconds)",
        )
    dev = np.abs(dt - Ts)
    k = int(np.argmax(dev))
    if dev[k] > SAMPLE_JITTER * Ts:
        raise DataError(
            path,
            k + 3,
            "time",
            f"sample step {float(dt[k]):g} s after line {k + 2} "
            f"differs from the median step {Ts:g} s by more than "
            f"{SAMPLE_JITTER:.0%} (sampling must be uniform)",
        )
    return Ts


#: fewest rows a command works with (a few Savitzky-Golay windows of the acceleration)
MIN_ROWS = 64
#: largest magnitude of a value in a column of the recording format: its square stays finite
MAX_ABS = 1e100


def check_plausible(run: Run) -> float:
    """:func:`check_sampling` plus: at least :data:`MIN_ROWS` rows, every value of a recording-format
    column within +-:data:`MAX_ABS`, and ``x`` or ``u`` not constant (a run that carries
    nothing).  Returns the median sample step [s]; raises :class:`DataError` naming the
    file, the line and the column."""
    path = run.path if run.path is not None else Path(run.name or "run")
    if run.n < MIN_ROWS:
        raise DataError(
            path,
            run.n + 1,
            "time",
            f"{run.n} data rows; the tools need at least {MIN_ROWS} (a few acceleration windows)",
        )
    for name, arr in run.columns().items():
        if name not in KNOWN_COLUMNS:
            continue
        big = np.flatnonzero(np.abs(arr) > MAX_ABS)
        if big.size:
            k = int(big[0])
            raise DataError(
                path,
                k + 2,
                name,
                f"value {float(arr[k])!r} is beyond +-{MAX_ABS:g} "
                "(no physical signal; its square overflows)",
            )
    if np.ptp(run.x) == 0 and np.ptp(run.u) == 0:
        raise DataError(path, None, "x", "x and u are constant: the run carries no information")
    return check_sampling(run)


def run_files(folder: str | Path) -> list[Path]:
    """Every recording in ``folder`` (``*.csv`` and ``*.csv.gz``, not recursive), sorted by
    file name.

    Raises ``NotADirectoryError`` when ``folder`` is not a directory, and :class:`DataError`
    when two recordings share a stem (``run.csv`` and ``run.csv.gz`` would share the sidecar
    ``run.json``).
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise NotADirectoryError(f"{folder}: not a directory")
    paths = sorted(
        {p for end in RUN_SUFFIXES for p in folder.glob(f"*{end}")}, key=lambda p: p.name
    )
    seen: dict[str, Path] = {}
    for p in paths:
        other = seen.setdefault(run_stem(p), p)
        if other != p:
            raise DataError(
                p,
                None,
                None,
                f"{other.name} is the same run's name: keep one "
                f"of the two (they would share the sidecar {run_stem(p)}.json)",
            )
    return paths


def load_runs(folder: str | Path) -> list[Run]:
    """Load every recording in ``folder`` (:func:`run_files`: ``*.csv``, ``*.csv.gz``),
    sorted by file name.

    Returns an empty list when the folder has no recording; raises ``NotADirectoryError``
    when ``folder`` is not a directory.
    """
    return [load_run(p) for p in run_files(folder)]


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"{type(obj).__name__} is not JSON serialisable")


def _cell(v: Any) -> str:
    return repr(float(v)) if isinstance(v, (float, np.floating)) else str(v)


#: Decimal places a recording carries per column of the recording format (:func:`write_run` ``decimals``):
#: positions to 1e-10 m (below any linear scale's resolution), voltage and current to 1e-7
#: (below any DAQ's), the load to 1e-7 N; ``time`` goes to its sample grid (:func:`time_text`).
RECORDING_DECIMALS: dict[str, int] = {"x": 10, "x_ref": 10, "u": 7, "i": 7, "F_load": 7}
#: gzip compression level of a ``.gz`` recording (6: about 1 % larger than level 9, 4x faster)
GZIP_LEVEL = 6
#: the most decimal places :func:`time_text` gives a sampled time
MAX_TIME_DECIMALS = 12


def fixed_text(values: np.ndarray, decimals: int) -> list[str]:
    """``values`` rounded to ``decimals`` places, as the shortest fixed-point text (no trailing
    zeros, no exponent, no "-0")."""
    rounded = np.round(np.asarray(values, dtype=float), decimals) + 0.0  # -0.0 -> 0.0
    if decimals <= 0:
        return [f"{v:.0f}" for v in rounded.tolist()]
    return [f"{v:.{decimals}f}".rstrip("0").rstrip(".") for v in rounded.tolist()]


def time_text(time: np.ndarray) -> list[str]:
    """Sample times as text on their grid: with ``Ts`` the median step written in the fewest
    decimal places (up to :data:`MAX_TIME_DECIMALS`) that change it by at most 1e-9 Ts, every
    time in those places when that moves none by more than 1e-6 Ts (``k * 0.0005`` is written
    ``0.0005 k`` exactly); times on no such grid keep every digit (``repr``)."""
    t = np.asarray(time, dtype=float)
    if len(t) >= 2:
        ts = float(np.median(np.diff(t)))
        if ts > 0:
            d = next(
                (d for d in range(MAX_TIME_DECIMALS + 1) if abs(round(ts, d) - ts) <= 1e-9 * ts),
                None,
            )
            if d is not None and np.max(np.abs(np.round(t, d) - t)) <= 1e-6 * ts:
                return fixed_text(t, d)
    return list(map(repr, t.tolist()))


def write_run(run: Run, path: str | Path, decimals: Mapping[str, int] | None = None) -> None:
    """Write ``run`` as a recording CSV, plus ``<stem>.json`` when ``run.meta`` is not empty.

    A ``path`` ending in ``.gz`` (``run.csv.gz``) is written gzip-compressed (no file name
    and time 0 in the gzip header: the same run gives the same bytes).

    The format's columns come first in the format's order, then ``run.extra`` in its order.  Floats are
    written with ``repr`` so that :func:`load_run` gives back the same float64 bits, except the
    columns named in ``decimals`` (a recording: :data:`RECORDING_DECIMALS`), each rounded to
    its number of decimal places, and then ``time`` on its sample grid (:func:`time_text`).
    A run the loader would reject (non-finite values, time not strictly increasing, < 2 rows)
    raises :class:`DataError` (line numbers are those the file would have) and nothing is
    written.  When ``run.meta`` is empty an existing sidecar at the destination is removed,
    so that the written pair describes ``run`` and nothing else.
    """
    path = Path(path)
    cols = run.columns()
    _check_values(path, {k: v for k, v in cols.items() if k in KNOWN_COLUMNS}, None)
    for name in cols:
        if not name.strip() or name != name.strip():
            raise DataError(
                path, 1, name, "column names must be non-empty without surrounding spaces"
            )
    jpath = sidecar_path(path)
    meta_text = None
    if run.meta:
        try:
            meta_text = json.dumps(run.meta, indent=2, allow_nan=False, default=_json_default)
        except (TypeError, ValueError) as e:
            raise DataError(jpath, None, None, f"run.meta is not valid JSON: {e}") from None
    names = list(cols)
    # each column to text once (repr of a Python float round-trips float64 exactly)
    decimals = dict(decimals or {})

    def text(c: str) -> list[str]:
        if np.asarray(cols[c]).dtype.kind != "f":
            return [_cell(v) for v in cols[c].tolist()]
        if c == "time" and decimals:
            return time_text(cols[c])
        if c in decimals:
            return fixed_text(cols[c], decimals[c])
        return list(map(repr, cols[c].tolist()))

    text_cols = [text(c) for c in names]
    buf = io.StringIO(newline="")
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(names)
    writer.writerows(zip(*text_cols, strict=True))
    data = buf.getvalue().encode("utf-8")
    if is_compressed(path):
        data = gzip.compress(data, compresslevel=GZIP_LEVEL, mtime=0)
    path.write_bytes(data)
    if meta_text is not None:
        jpath.write_text(meta_text + "\n", encoding="utf-8")
    elif jpath.exists():
        jpath.unlink()
