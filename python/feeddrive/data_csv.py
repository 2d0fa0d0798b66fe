"""The CSV text of a recording: bounded reading, strict number syntax, header and value checks.

:func:`read_columns` reads a run CSV into float64 columns (and the other columns as float or
str) with memory bounded in chunks: a fast path through numpy's C parser for plain numeric
files, else the exact csv-module reader that finds and locates every problem.  The header row
must end within :data:`MAX_HEADER_BYTES`, a line within :data:`MAX_LINE_CHARS`; a number is
plain ASCII decimal with an optional exponent (:data:`_NUMBER`).  :func:`_check_values` holds
the rules on the values (finite, time strictly increasing, at least 2 rows).  Every broken
rule raises :class:`DataError` naming the file, the 1-based line and the column.  The public
face of runs (``Run``, ``load_run``, ``write_run``) is :mod:`feeddrive.data`.

A recording whose name ends in ``.gz`` (``run.csv.gz``) is gzip-compressed CSV: it is
streamed through :mod:`gzip` with the same chunks, rules and messages as a plain one (line
numbers count the decompressed text); a file that is no valid gzip stream, or ends early,
raises :class:`DataError` naming it.
"""

from __future__ import annotations

import codecs
import csv
import gzip
import io
import re
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import IO

import numpy as np

from .inputs import InputFileError, open_input

#: Every column the recording format defines, in the order the writer puts them.
KNOWN_COLUMNS: tuple[str, ...] = ("time", "u", "i", "x", "x_ref", "F_load")
#: Columns a run must have.
REQUIRED_COLUMNS: tuple[str, ...] = ("time", "u", "x")
#: File name endings of a recording: plain CSV and gzip-compressed CSV.
RUN_SUFFIXES: tuple[str, ...] = (".csv", ".csv.gz")


def is_compressed(path: str | Path) -> bool:
    """True when ``path`` names a gzip-compressed file (its name ends in ``.gz``)."""
    return Path(path).name.lower().endswith(".gz")


def run_stem(path: str | Path) -> str:
    """The name of a recording without its ending (``.csv.gz``, ``.csv``, or the last
    suffix): ``run.csv.gz`` -> ``run``."""
    name = Path(path).name
    for end in sorted(RUN_SUFFIXES, key=len, reverse=True):
        if name.lower().endswith(end) and len(name) > len(end):
            return name[: -len(end)]
    return Path(path).stem


class DataError(ValueError):
    """A run file (or its JSON sidecar) that breaks the recording format.

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


def _decode_error(path: Path, e: UnicodeDecodeError) -> DataError:
    """The file's first invalid byte as a DataError with its line (reads the bytes again, in
    blocks: the memory stays bounded whatever the file's size)."""
    dec = codecs.getincrementaldecoder("utf-8-sig")()
    offset, line = 0, 1
    with _open_bytes(path) as f:
        while block := f.read(_CHUNK_CHARS):
            try:
                dec.decode(block)
            except UnicodeDecodeError as err:
                at = max(0, min(err.start - len(err.object) + len(block), len(block)))
                line += block[:at].count(b"\n")
                return DataError(
                    path, line, None, f"not UTF-8 text (byte {offset + at}: {err.reason})"
                )
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


class _Gzip(gzip.GzipFile):
    """A gzip stream that closes the file it reads when it is closed."""

    def __init__(self, raw: IO[bytes]) -> None:
        self._raw = raw
        super().__init__(fileobj=raw, mode="rb")

    def close(self) -> None:
        try:
            super().close()
        finally:
            self._raw.close()


def _open_bytes(path: Path) -> IO[bytes] | gzip.GzipFile:
    """The bytes of the recording ``path``: decompressed on the fly for a ``.gz`` file."""
    f = open_input(path, encoding=None)
    if not is_compressed(path):
        return f
    try:
        if not f.read(2):  # gzip reads an empty file as an empty stream
            raise gzip.BadGzipFile("empty file")
        f.seek(0)
        return _Gzip(f)
    except BaseException:
        f.close()
        raise


def _open(path: Path) -> IO[str]:
    if not is_compressed(path):
        return open_input(path, encoding="utf-8-sig")
    return io.TextIOWrapper(_open_bytes(path), encoding="utf-8-sig", newline="")


#: what a broken gzip stream raises while it is read (bad header or CRC, truncated, bad data)
_GZIP_ERRORS = (gzip.BadGzipFile, EOFError, zlib.error)


def _gzip_error(path: Path, e: BaseException) -> DataError:
    what = str(e) or type(e).__name__
    return DataError(
        path, None, None, f"not a valid gzip file ({what}): a .gz recording is gzip-compressed CSV"
    )


#: the header row must end within this many bytes (a few KiB of column names; a file without
#: a line end there is no recording CSV, and is not read further for the message)
MAX_HEADER_BYTES = 1 << 16

#: a number: plain ASCII decimal with an optional exponent, or the words nan/inf (refused
#: later as non-finite, with that message), spaces or tabs around
_NUMBER = (
    r"[ \t]*[+-]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
    r"|(?i:nan|inf|infinity))[ \t]*"
)
_NUMBER_RE = re.compile(_NUMBER)
#: the ASCII characters that Python's float() or numpy's parser take in a number beyond
#: :data:`_NUMBER` ('_' between digits, control characters as spaces) and the quote: a text
#: that is ASCII and holds none of them is read by both parsers exactly as the syntax says
#: (any other character makes the number unreadable to them)
_NOT_IN_NUMBERS = '_"\x00\x0b\x0c\x1c\x1d\x1e\x1f'
_NUMBER_RULE = (
    "numbers are plain ASCII decimal: digits 0-9, one '.', an optional exponent "
    "e/E (no '_', no digits of other scripts)"
)


def _check_header_bytes(path: Path) -> None:
    """The header row ends within :data:`MAX_HEADER_BYTES` and holds no NUL byte (reads at
    most that many bytes)."""
    with _open_bytes(path) as f:
        head = f.read(MAX_HEADER_BYTES)
    end = min((k for k in (head.find(b"\n"), head.find(b"\r")) if k >= 0), default=-1)
    if end < 0 and len(head) == MAX_HEADER_BYTES:
        raise DataError(
            path,
            1,
            None,
            f"no line end in the first {MAX_HEADER_BYTES} bytes: the "
            "header row of a recording CSV is one short line of column names (starts "
            f"{_short(head[:40].decode('utf-8', 'replace'), 40)!r})",
        )
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
    if (
        joined.count(",") != len(cells) - 1
        or "\n" in joined
        or "\r" in joined
        or not _ascii_plain(joined)
    ):
        return None
    try:
        return np.array(cells, dtype=float)
    except ValueError:
        return None


#: longest line of a run CSV [characters]; a longer one is refused without being read whole
MAX_LINE_CHARS = 1 << 22


def _too_long(path: Path, line: int) -> DataError:
    return DataError(
        path,
        line,
        None,
        f"line longer than {MAX_LINE_CHARS} characters: not a recording row (not read further)",
    )


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
            carry = lines.pop()  # may go on in the next block (a "\r\n" cut in two too)
            if len(carry) > MAX_LINE_CHARS:
                raise _too_long(path, done + len(lines) + 1)
        if not lines and not block:
            return
        # only the first line holds the carry; the others fit in the block
        if lines and (
            len(lines[0]) > MAX_LINE_CHARS
            or (len(block) > MAX_LINE_CHARS and max(map(len, lines)) > MAX_LINE_CHARS)
        ):
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
                raise _NotPlain  # quotes, '_', other digits: the strict reader
            try:
                a = (
                    np.loadtxt(lines, delimiter=",", comments=None, dtype=float, ndmin=2)
                    if not text.isspace()
                    else np.empty((0, len(names)))
                )
            except ValueError:
                raise _NotPlain from None
            if a.shape[1:] != (len(names),):
                raise _NotPlain
            if a.shape[0] != len(lines):  # blank lines: only at the end of the file
                k = a.shape[0]
                if (
                    any(ln in _BLANK for ln in lines[:k])
                    or any(ln not in _BLANK for ln in lines[k:])
                    or any(ln not in _BLANK for rest in chunks for ln in rest)
                ):
                    raise _NotPlain
            parts.append(a)
    cols = {
        n: np.concatenate([p[:, k] for p in parts]) if parts else np.empty(0)
        for k, n in enumerate(names)
    }
    return names, cols


def _read_strict(
    path: Path,
) -> tuple[list[str], dict[str, np.ndarray], dict[str, np.ndarray], list[int]]:
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
                    col = (
                        names[len(row)] if len(row) < width else f"#{width + 1} (beyond the header)"
                    )
                    raise DataError(
                        path, reader.line_num, col, f"{len(row)} fields, the header has {width}"
                    )
                rows.append(row)
                rows_at.append(reader.line_num)  # last physical line of the record
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


def _take_chunk(
    path: Path,
    names: list[str],
    rows: list[list[str]],
    rows_at: list[int],
    known: dict[str, list[np.ndarray]],
    text: dict[str, list[str]],
) -> None:
    if not rows:
        return
    for name, cells in zip(names, zip(*rows, strict=True), strict=True):
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
            raise DataError(
                path, 1, name, f"duplicate column name (fields {seen[name] + 1} and {k + 1})"
            )
        seen[name] = k
    for req in REQUIRED_COLUMNS:
        if req not in seen:
            hint = [n for n in names if n.lower() == req.lower()]
            extra = f" (found {hint[0]!r}: names are case-sensitive)" if hint else ""
            raise DataError(
                path, 1, req, f"required column missing; header has {','.join(names)}{extra}"
            )
    return names


def _to_float(
    path: Path, column: str, cells: tuple[str, ...] | list[str], lines: list[int]
) -> np.ndarray:
    floats = _floats(cells)
    if floats is not None:
        return floats
    for cell, line in zip(cells, lines, strict=True):
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
            raise DataError(
                path,
                line_of(k),
                name,
                f"non-finite value {float(arr[k])!r}"
                + (f" ({bad.size} in this column)" if bad.size > 1 else ""),
            )
    t = cols["time"]
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        k = int(back[0]) + 1
        what = "repeats" if t[k] == t[k - 1] else "goes backwards"
        raise DataError(
            path,
            line_of(k),
            "time",
            f"time {what}: {float(t[k])!r} after {float(t[k - 1])!r} on line {line_of(k - 1)}; "
            "time must increase strictly",
        )


def read_columns(
    path: Path,
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray], list[int] | None]:
    """The run CSV at ``path`` as (the format's columns, other columns, each row's line or None
    when row k is line k + 2); the values are not checked yet (:func:`_check_values`).

    Raises :class:`DataError` for a broken rule of the CSV text (header, fields, numbers,
    encoding, line lengths) or a file that cannot be read as an input.
    """
    try:
        _check_header_bytes(path)
        _, every = _read_plain(path)
    except InputFileError as e:
        raise DataError(path, None, None, e.problem) from None
    except _NotPlain:
        try:
            _, cols, extra, lines = _read_strict(path)
        except _GZIP_ERRORS as e:
            raise _gzip_error(path, e) from None
    except UnicodeDecodeError as e:
        raise _decode_error(path, e) from None
    except _GZIP_ERRORS as e:
        raise _gzip_error(path, e) from None
    else:
        cols = {n: v for n, v in every.items() if n in KNOWN_COLUMNS}
        extra = {n: v for n, v in every.items() if n not in KNOWN_COLUMNS}
        return cols, extra, None  # plain file: row k is line k + 2
    return cols, extra, lines
