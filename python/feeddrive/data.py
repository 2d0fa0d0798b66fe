"""Measured-data runs: the loader and writer of ``shared/DATA.md``.

A run is one CSV file with a header row (columns ``time, u, i, x, x_ref, F_load`` in SI,
``time``, ``u``, ``x`` required; any other column is kept as it is) plus an optional JSON
sidecar with the same stem (``run.csv`` + ``run.json``) that says how the experiment was run
(the runs our commands write use one schema for it: :mod:`feeddrive.harness.sidecar`).

The loader is strict: every rule of DATA.md that a file breaks raises :class:`DataError`
naming the file, the 1-based line (the header is line 1) and the column.  Rows are never
dropped or reordered.  A run and its sidecar must be regular files (a FIFO or a device is
refused before it is read); the header row must end within :data:`MAX_HEADER_BYTES`; a number
is plain ASCII decimal with an optional exponent (``-1.5e-3``; ``nan``/``inf`` are read and
then refused as non-finite), never what Python's ``float`` also takes (``0.1_2``, digits of
other scripts).  The writer refuses a run the loader would reject and writes floats
with ``repr`` (the shortest string that round-trips a float64 exactly).
"""
from __future__ import annotations

import codecs
import csv
import io
import json
import os
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .inputs import InputFileError, open_input, read_text

#: Every column DATA.md defines, in the order the writer puts them.
KNOWN_COLUMNS: tuple[str, ...] = ("time", "u", "i", "x", "x_ref", "F_load")
#: Columns a run must have.
REQUIRED_COLUMNS: tuple[str, ...] = ("time", "u", "x")
_OPTIONAL_COLUMNS = tuple(c for c in KNOWN_COLUMNS if c not in REQUIRED_COLUMNS)


class DataError(ValueError):
    """A run file (or its JSON sidecar) that breaks DATA.md.

    Attributes ``path``, ``line`` (1-based, header = 1; ``None`` when no line applies) and
    ``column`` (``None`` for a sidecar) locate the problem; the message says all three.
    """

    def __init__(self, path: str | Path, line: int | None, column: str | None, problem: str):
        self.path = Path(path)
        self.line = line
        self.column = column
        self.problem = problem
        where = [str(self.path)]
        if line is not None:
            where.append(f"line {line}")
        if column is not None:
            where.append(f"column {_short(column)!r}")
        super().__init__(f"{', '.join(where)}: {problem}")


def _short(text: str, n: int = 80) -> str:
    """``text`` cut to ``n`` characters (with "...") for a message."""
    return text if len(text) <= n else text[:n] + "..."


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
                raise ValueError(f"Run: extra column {k!r} clashes with a DATA.md column")
            if v.ndim != 1:
                raise ValueError(f"Run: extra column {k!r} must be 1-D, got shape {v.shape}")
        n = len(self.time)
        for name, arr in self.columns().items():
            if len(arr) != n:
                raise ValueError(f"Run: column {name!r} has {len(arr)} samples, time has {n}")
        if self.path is not None:
            self.path = Path(self.path)

    def columns(self) -> dict[str, np.ndarray]:
        """Every present column, DATA.md columns first (in DATA.md order), then ``extra``."""
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
        """The file's stem, or ``meta['name']`` / "" for a run not read from a file."""
        if self.path is not None:
            return self.path.stem
        return str(self.meta.get("name", ""))


def sidecar_path(path: str | Path) -> Path:
    """The JSON sidecar that belongs to a run CSV (same stem, ``.json``)."""
    return Path(path).with_suffix(".json")


def _decode_error(path: Path, e: UnicodeDecodeError) -> DataError:
    """The file's first invalid byte as a DataError with its line (reads the bytes again, in
    blocks: the memory stays bounded whatever the file's size)."""
    dec = codecs.getincrementaldecoder("utf-8-sig")()
    offset, line = 0, 1
    with open_input(path, encoding=None) as f:
        while block := f.read(_CHUNK_CHARS):
            try:
                dec.decode(block)
            except UnicodeDecodeError as err:
                at = max(0, min(err.start - len(err.object) + len(block), len(block)))
                line += block[:at].count(b"\n")
                return DataError(path, line, None,
                                 f"not UTF-8 text (byte {offset + at}: {err.reason})")
            line += block.count(b"\n")
            offset += len(block)
    return DataError(path, None, None, f"not UTF-8 text ({e.reason})")


class _NotPlain(Exception):
    """The file is not plain numeric CSV (quotes, blank lines, text cells, ragged rows...):
    the strict reader takes over and finds the problem or reads it exactly."""


#: characters of text per chunk (bounds the loader's working memory)
_CHUNK_CHARS = 1 << 22
#: records per chunk of the strict reader
_CHUNK_ROWS = 1 << 15


_BLANK = frozenset({"\n", "\r\n", "\r", ""})


def _open(path: Path):
    return open_input(path, encoding="utf-8-sig")


#: the header row must end within this many bytes (a few KiB of column names; a file without
#: a line end there is no DATA.md CSV, and is not read further for the message)
MAX_HEADER_BYTES = 1 << 16

#: a number: plain ASCII decimal with an optional exponent, or the words nan/inf (refused
#: later as non-finite, with that message), spaces or tabs around
_NUMBER = (r"[ \t]*[+-]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
           r"|(?i:nan|inf|infinity))[ \t]*")
_NUMBER_RE = re.compile(_NUMBER)
#: the ASCII characters that Python's float() or numpy's parser take in a number beyond
#: :data:`_NUMBER` ('_' between digits, control characters as spaces) and the quote: a text
#: that is ASCII and holds none of them is read by both parsers exactly as the syntax says
#: (any other character makes the number unreadable to them)
_NOT_IN_NUMBERS = '_"\x00\x0b\x0c\x1c\x1d\x1e\x1f'
_NUMBER_RULE = ("numbers are plain ASCII decimal: digits 0-9, one '.', an optional exponent "
                "e/E (no '_', no digits of other scripts)")


def _check_header_bytes(path: Path) -> None:
    """The header row ends within :data:`MAX_HEADER_BYTES` and holds no NUL byte (reads at
    most that many bytes)."""
    with open_input(path, encoding=None) as f:
        head = f.read(MAX_HEADER_BYTES)
    end = min((k for k in (head.find(b"\n"), head.find(b"\r")) if k >= 0), default=-1)
    if end < 0 and len(head) == MAX_HEADER_BYTES:
        raise DataError(path, 1, None, f"no line end in the first {MAX_HEADER_BYTES} bytes: the "
                        "header row of a DATA.md CSV is one short line of column names (starts "
                        f"{_short(head[:40].decode('utf-8', 'replace'), 40)!r})")
    if b"\0" in (head if end < 0 else head[:end]):
        raise DataError(path, 1, None, "NUL byte in the header row: not a text CSV")


def _ascii_plain(text: str) -> bool:
    """True when ``text`` is ASCII without a character of :data:`_NOT_IN_NUMBERS` (a few
    passes in C over the text, no regex per cell)."""
    return text.isascii() and not any(c in text for c in _NOT_IN_NUMBERS)


def _floats(cells: tuple[str, ...] | list[str]) -> np.ndarray | None:
    """The cells as float64 when every one is a number of the syntax :data:`_NUMBER`, else
    None (checked on the cells' joined text, then parsed by numpy)."""
    if not cells:
        return np.empty(0)
    joined = ",".join(cells)
    if joined.count(",") != len(cells) - 1 or "\n" in joined or "\r" in joined \
            or not _ascii_plain(joined):
        return None
    try:
        return np.array(cells, dtype=float)
    except ValueError:
        return None


#: longest line of a run CSV [characters]; a longer one is refused without being read whole
MAX_LINE_CHARS = 1 << 22


def _too_long(path: Path, line: int) -> DataError:
    return DataError(path, line, None, f"line longer than {MAX_LINE_CHARS} characters: not a "
                     "DATA.md row (not read further)")


def _line_chunks(f, path: Path) -> Iterator[list[str]]:
    """The remaining lines of the text file ``f`` (line ends kept) in lists of about
    :data:`_CHUNK_CHARS` characters, read in blocks of that size; a line longer than
    :data:`MAX_LINE_CHARS` raises :class:`DataError` (line numbers count the header as 1).
    ``str.splitlines`` also splits at rarer separators (form feed, U+2028...): those are no
    plain numeric text, and the fast path hands such a file to the strict reader."""
    carry, done = "", 1
    while True:
        block = f.read(_CHUNK_CHARS)
        lines = (carry + block).splitlines(keepends=True)
        carry = ""
        if block and lines and (lines[-1][-1] not in "\r\n" or lines[-1][-1] == "\r"):
            carry = lines.pop()         # may go on in the next block (a "\r\n" cut in two too)
            if len(carry) > MAX_LINE_CHARS:
                raise _too_long(path, done + len(lines) + 1)
        if not lines and not block:
            return
        # only the first line holds the carry; the others fit in the block
        if lines and (len(lines[0]) > MAX_LINE_CHARS
                      or len(block) > MAX_LINE_CHARS and max(map(len, lines)) > MAX_LINE_CHARS):
            k = next(k for k, ln in enumerate(lines) if len(ln) > MAX_LINE_CHARS)
            raise _too_long(path, done + k + 1)
        done += len(lines)
        if lines:
            yield lines


def _bounded_lines(f, path: Path) -> Iterator[str]:
    """The lines of the text file ``f`` one by one (as iterating it gives them), each at most
    :data:`MAX_LINE_CHARS` characters, else :class:`DataError`."""
    n = 0
    while line := f.readline(MAX_LINE_CHARS + 1):
        n += 1
        if len(line) > MAX_LINE_CHARS:
            raise _too_long(path, n)
        yield line


def _read_plain(path: Path) -> tuple[list[str], dict[str, np.ndarray]]:
    """Fast path: header and every cell as float64 through numpy's C parser, in chunks.

    Raises :class:`_NotPlain` unless every data line is ``width`` unquoted numbers (no quote,
    blank lines only at the end), so that row k of the result is line k + 2 of the file.
    """
    parts: list[np.ndarray] = []
    with _open(path) as f:
        head = f.readline()
        if not head.strip() or '"' in head:
            raise _NotPlain
        names = _check_header(path, head.rstrip("\r\n").split(","))
        chunks = _line_chunks(f, path)
        for lines in chunks:
            text = "".join(lines)
            if not _ascii_plain(text):
                raise _NotPlain             # quotes, '_', other digits: the strict reader
            try:
                a = np.loadtxt(lines, delimiter=",", comments=None, dtype=float, ndmin=2) \
                    if not text.isspace() else np.empty((0, len(names)))
            except ValueError:
                raise _NotPlain from None
            if a.shape[1:] != (len(names),):
                raise _NotPlain
            if a.shape[0] != len(lines):     # blank lines: only at the end of the file
                k = a.shape[0]
                if any(ln in _BLANK for ln in lines[:k]) or any(ln not in _BLANK for ln in lines[k:]) \
                        or any(ln not in _BLANK for rest in chunks for ln in rest):
                    raise _NotPlain
            parts.append(a)
    cols = {n: np.concatenate([p[:, k] for p in parts]) if parts else np.empty(0)
            for k, n in enumerate(names)}
    return names, cols


def _read_strict(path: Path) -> tuple[list[str], dict[str, np.ndarray], dict[str, np.ndarray],
                                      list[int]]:
    """Exact path (csv module, streaming, chunks of records): header, known columns as
    float64, other columns (float when every cell is a number, else str), each row's line."""
    known: dict[str, list[np.ndarray]] = {}
    text: dict[str, list[str]] = {}
    lines: list[int] = []
    with _open(path) as f:
        reader = csv.reader(_bounded_lines(f, path), strict=True)
        try:
            header = next(reader, None)
            if header is None:
                raise DataError(path, 1, None, "empty file: no header row")
            names = _check_header(path, header)
            width = len(names)
            known = {n: [] for n in names if n in KNOWN_COLUMNS}
            text = {n: [] for n in names if n not in KNOWN_COLUMNS}
            rows: list[list[str]] = []
            rows_at: list[int] = []
            blank_at: int | None = None
            for row in reader:
                if not row:
                    blank_at = blank_at or reader.line_num
                    continue
                if blank_at is not None:
                    raise DataError(path, blank_at, names[0], "blank line inside the data")
                if len(row) != width:
                    col = names[len(row)] if len(row) < width else f"#{width + 1} (beyond the header)"
                    raise DataError(path, reader.line_num, col,
                                    f"{len(row)} fields, the header has {width}")
                rows.append(row)
                rows_at.append(reader.line_num)   # last physical line of the record
                if len(rows) == _CHUNK_ROWS:
                    _take_chunk(path, names, rows, rows_at, known, text)
                    lines += rows_at
                    rows, rows_at = [], []
            _take_chunk(path, names, rows, rows_at, known, text)
            lines += rows_at
        except csv.Error as e:
            raise DataError(path, reader.line_num, None, f"malformed CSV: {e}") from None
        except UnicodeDecodeError as e:
            raise _decode_error(path, e) from None
    cols = {n: np.concatenate(v) if v else np.empty(0) for n, v in known.items()}
    extra: dict[str, np.ndarray] = {}
    for n, cells in text.items():
        floats = _floats(cells)
        extra[n] = floats if floats is not None else np.array(cells, dtype=str)
    return names, cols, extra, lines


def _take_chunk(path: Path, names: list[str], rows: list[list[str]], rows_at: list[int],
                known: dict[str, list[np.ndarray]], text: dict[str, list[str]]) -> None:
    if not rows:
        return
    for name, cells in zip(names, zip(*rows)):
        if name in known:
            known[name].append(_to_float(path, name, cells, rows_at))
        else:
            text[name].extend(cells)


def _check_header(path: Path, header: list[str]) -> list[str]:
    names = [h.strip() for h in header]
    seen: dict[str, int] = {}
    for k, name in enumerate(names):
        if not name:
            raise DataError(path, 1, f"#{k + 1}", "empty column name in the header")
        if name in seen:
            raise DataError(path, 1, name,
                            f"duplicate column name (fields {seen[name] + 1} and {k + 1})")
        seen[name] = k
    for req in REQUIRED_COLUMNS:
        if req not in seen:
            hint = [n for n in names if n.lower() == req.lower()]
            extra = f" (found {hint[0]!r}: names are case-sensitive)" if hint else ""
            raise DataError(path, 1, req,
                            f"required column missing; header has {','.join(names)}{extra}")
    return names


def _to_float(path: Path, column: str, cells: tuple[str, ...] | list[str],
              lines: list[int]) -> np.ndarray:
    floats = _floats(cells)
    if floats is not None:
        return floats
    for cell, line in zip(cells, lines):
        if not _NUMBER_RE.fullmatch(cell):
            raise DataError(path, line, column, f"not a number: {_short(cell)!r} ({_NUMBER_RULE})")
    raise DataError(path, lines[0] if lines else None, column, f"not numbers ({_NUMBER_RULE})")


def _check_values(path: Path, cols: dict[str, np.ndarray], lines: list[int] | None) -> None:
    """Finite known columns, strictly increasing time, at least 2 rows."""
    def line_of(k: int) -> int:
        return lines[k] if lines is not None else k + 2
    n = len(cols["time"])
    if n < 2:
        last = line_of(n - 1) if n else 1
        raise DataError(path, last, "time", f"{n} data row(s); a run needs at least 2")
    for name in KNOWN_COLUMNS:
        if name not in cols:
            continue
        arr = cols[name]
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            k = int(bad[0])
            raise DataError(path, line_of(k), name, f"non-finite value {float(arr[k])!r}"
                            + (f" ({bad.size} in this column)" if bad.size > 1 else ""))
    t = cols["time"]
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        k = int(back[0]) + 1
        what = "repeats" if t[k] == t[k - 1] else "goes backwards"
        raise DataError(path, line_of(k), "time",
                        f"time {what}: {float(t[k])!r} after {float(t[k - 1])!r} on line {line_of(k - 1)}; "
                        "time must increase strictly")


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
        raise DataError(jpath, e.lineno, None,
                        f"invalid sidecar JSON at column {e.colno}: {e.msg}") from None
    except RecursionError:
        raise DataError(jpath, None, None, "sidecar JSON nested too deeply") from None
    if not isinstance(meta, dict):
        raise DataError(jpath, 1, None,
                        f"sidecar JSON must be an object, got {type(meta).__name__}")
    return meta


def load_run(path: str | Path) -> Run:
    """Read one DATA.md run (CSV plus its optional JSON sidecar).

    Parameters
    ----------
    path : str or Path
        The CSV file.

    Returns
    -------
    Run
        Columns as float64 arrays; unknown columns in ``extra`` (float when every cell is a
        number, else str); ``meta`` from the sidecar or {}.

    Raises
    ------
    DataError
        For every broken rule of DATA.md (missing required column, duplicate column name,
        row with the wrong number of fields, non-numeric or non-finite value in a known
        column, time not strictly increasing, fewer than 2 rows, invalid sidecar JSON),
        naming the file, line and column.
    """
    path = Path(path)
    try:
        _check_header_bytes(path)
        names, every = _read_plain(path)
    except InputFileError as e:
        raise DataError(path, None, None, e.problem) from None
    except _NotPlain:
        names, cols, extra, lines = _read_strict(path)
    except UnicodeDecodeError as e:
        raise _decode_error(path, e) from None
    else:
        cols = {n: v for n, v in every.items() if n in KNOWN_COLUMNS}
        extra = {n: v for n, v in every.items() if n not in KNOWN_COLUMNS}
        lines = None            # plain file: row k is line k + 2
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
        raise DataError(path, None, "time", f"median sample step {Ts:g} s is outside {lo:g} .. "
                        f"{hi:g} s (time must be in seconds)")
    dev = np.abs(dt - Ts)
    k = int(np.argmax(dev))
    if dev[k] > SAMPLE_JITTER * Ts:
        raise DataError(path, k + 3, "time", f"sample step {float(dt[k]):g} s after line {k + 2} "
                        f"differs from the median step {Ts:g} s by more than "
                        f"{SAMPLE_JITTER:.0%} (sampling must be uniform)")
    return Ts


#: fewest rows a command works with (a few Savitzky-Golay windows of the acceleration)
MIN_ROWS = 64
#: largest magnitude of a value in a DATA.md column: its square stays finite
MAX_ABS = 1e100


def check_plausible(run: Run) -> float:
    """:func:`check_sampling` plus: at least :data:`MIN_ROWS` rows, every value of a DATA.md
    column within +-:data:`MAX_ABS`, and ``x`` or ``u`` not constant (a run that carries
    nothing).  Returns the median sample step [s]; raises :class:`DataError` naming the
    file, the line and the column."""
    path = run.path if run.path is not None else Path(run.name or "run")
    if run.n < MIN_ROWS:
        raise DataError(path, run.n + 1, "time", f"{run.n} data rows; the tools need at least "
                        f"{MIN_ROWS} (a few acceleration windows)")
    for name, arr in run.columns().items():
        if name not in KNOWN_COLUMNS:
            continue
        big = np.flatnonzero(np.abs(arr) > MAX_ABS)
        if big.size:
            k = int(big[0])
            raise DataError(path, k + 2, name, f"value {float(arr[k])!r} is beyond +-{MAX_ABS:g} "
                            "(no physical signal; its square overflows)")
    if np.ptp(run.x) == 0 and np.ptp(run.u) == 0:
        raise DataError(path, None, "x", "x and u are constant: the run carries no information")
    return check_sampling(run)


def load_runs(folder: str | Path) -> list[Run]:
    """Load every ``*.csv`` in ``folder`` (not recursive), sorted by file name.

    Returns an empty list when the folder has no CSV file; raises ``NotADirectoryError``
    when ``folder`` is not a directory.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise NotADirectoryError(f"{folder}: not a directory")
    return [load_run(p) for p in sorted(folder.glob("*.csv"), key=lambda p: p.name)]


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


def write_run(run: Run, path: str | Path) -> None:
    """Write ``run`` as a DATA.md CSV, plus ``<stem>.json`` when ``run.meta`` is not empty.

    DATA.md columns come first in DATA.md order, then ``run.extra`` in its order.  Floats are
    written with ``repr`` so that :func:`load_run` gives back the same float64 bits.  A run
    the loader would reject (non-finite values, time not strictly increasing, < 2 rows)
    raises :class:`DataError` (line numbers are those the file would have) and nothing is
    written.  When ``run.meta`` is empty an existing sidecar at the destination is removed,
    so that the written pair describes ``run`` and nothing else.
    """
    path = Path(path)
    cols = run.columns()
    _check_values(path, {k: v for k, v in cols.items() if k in KNOWN_COLUMNS}, None)
    for name in cols:
        if not name.strip() or name != name.strip():
            raise DataError(path, 1, name, "column names must be non-empty without "
                            "surrounding spaces")
    jpath = sidecar_path(path)
    meta_text = None
    if run.meta:
        try:
            meta_text = json.dumps(run.meta, indent=2, allow_nan=False, default=_json_default)
        except (TypeError, ValueError) as e:
            raise DataError(jpath, None, None, f"run.meta is not valid JSON: {e}") from None
    names = list(cols)
    # each column to text once (repr of a Python float round-trips float64 exactly)
    text_cols = [list(map(repr, cols[c].tolist())) if np.asarray(cols[c]).dtype.kind == "f"
                 else [_cell(v) for v in cols[c].tolist()] for c in names]
    buf = io.StringIO(newline="")
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(names)
    writer.writerows(zip(*text_cols))
    path.write_text(buf.getvalue(), encoding="utf-8", newline="")
    if meta_text is not None:
        jpath.write_text(meta_text + "\n", encoding="utf-8")
    elif jpath.exists():
        jpath.unlink()

