"""Reading the files a command is given: regular files only, bounded reads, one-line names.

- :func:`open_input` opens a regular file and refuses anything else (a FIFO would block the
  reader forever, a device such as ``/dev/zero`` never ends, a folder or a socket is no
  file): the path is checked with ``stat`` before it is opened and the opened descriptor
  again (non-blocking open, ``fstat``), so a file swapped in between is refused too.
- :func:`read_text` reads such a file whole, refusing one larger than a limit (model, study
  and sidecar files are small JSON documents).
- :func:`one_line` escapes the control characters of a text (a newline in a file name would
  split a one-line message) the way ``repr`` does.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path
from typing import IO

#: largest JSON file read whole (model, study, sidecar) [bytes]
MAX_TEXT_BYTES = 16 << 20

_KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


class InputFileError(ValueError):
    """A path given as an input file that is not a readable regular file.

    ``path`` is the path, ``problem`` the rule it breaks (without the path)."""

    def __init__(self, path: str | Path, problem: str) -> None:
        self.path = Path(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")


def _kind(mode: int) -> str | None:
    """What a non-regular file is ("a FIFO (named pipe)" ...); None for a regular file."""
    if stat.S_ISREG(mode):
        return None
    return next((name for test, name in _KINDS if test(mode)), "a special file")


def check_regular(path: str | Path) -> None:
    """Raise :class:`InputFileError` unless ``path`` (links followed) is a regular file.

    A missing file raises the ``FileNotFoundError`` of ``os.stat``."""
    try:
        mode = os.stat(path).st_mode
    except OSError as e:
        if e.errno == errno.ELOOP:
            raise InputFileError(path, "is a symbolic link loop, not a regular file") from None
        raise
    kind = _kind(mode)
    if kind is not None:
        raise InputFileError(path, f"is {kind}, not a regular file")


def open_input(path: str | Path, encoding: str | None = "utf-8") -> IO:
    """Open the regular file ``path`` for reading (text with ``encoding`` and ``newline=""``,
    or bytes when ``encoding`` is None); :class:`InputFileError` for any other kind of file.
    """
    check_regular(path)
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    try:
        kind = _kind(os.fstat(fd).st_mode)
        if kind is not None:
            raise InputFileError(path, f"is {kind}, not a regular file")
        os.set_blocking(fd, True)
        if encoding is None:
            return os.fdopen(fd, "rb")
        return os.fdopen(fd, "r", encoding=encoding, newline="")
    except BaseException:
        os.close(fd)
        raise


def read_text(path: str | Path, limit: int = MAX_TEXT_BYTES, encoding: str = "utf-8") -> str:
    """The text of the regular file ``path`` (universal newlines), at most ``limit`` bytes.

    Raises :class:`InputFileError` for a special file or a larger one, ``UnicodeDecodeError``
    for bytes that are not ``encoding``."""
    with open_input(path, encoding=None) as f:
        raw = f.read(limit + 1)
    if len(raw) > limit:
        raise InputFileError(
            path, f"is larger than {limit >> 20} MiB: not a JSON document of this kind"
        )
    return raw.decode(encoding).replace("\r\n", "\n").replace("\r", "\n")


def one_line(text: str) -> str:
    """``text`` with every control character and line or paragraph separator escaped as
    ``repr`` writes it (``\\n``, ``\\x1b``, ``\\u2028``): it prints as one line."""
    return "".join(c if c.isprintable() or c == " " else repr(c)[1:-1] for c in text)
