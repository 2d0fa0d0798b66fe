"""Where commands write: checked before any work, never over an input, in place at once.

- A **file** output (a model file) is checked first (:func:`check_file`: not an input, not a
  folder, its folder creatable and writable) and written with :func:`write_text` (a
  temporary file beside it, then ``os.replace``: a reader sees the old or the new file).
- A **folder** output (a report, a diagnosis, a campaign) is one run's results only:
  :func:`output_dir` checks the target (:func:`check_dir`), gives a fresh temporary folder
  beside it to write into, and on success moves it into place, replacing the previous
  results; on an error the temporary folder is removed and the target is untouched.  A
  folder we wrote holds :data:`MARKER`; an existing non-empty folder without it is refused
  unless ``force`` (then it is replaced).  A target that holds an input, is an input, or
  holds the working directory is always refused.

Every refusal is an :class:`OutputError` (a ValueError) naming the path and the rule.
"""
from __future__ import annotations

import json
import os
import shutil
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

#: the file that marks a folder as written by feeddrive
MARKER = ".feeddrive-output"


class OutputError(ValueError):
    """An output path that cannot or must not be written; names the path and the rule."""


def _inside(path: Path, folder: Path) -> bool:
    return path == folder or folder in path.parents


def _resolved(paths: Iterable[str | Path | None]) -> list[Path]:
    return [Path(p).resolve() for p in paths if p is not None]


def _probe(folder: Path, what: str) -> None:
    """Create ``folder`` (and parents) and write a temporary file in it."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(prefix=".feeddrive-probe-", dir=folder)
        os.close(fd)
        os.unlink(name)
    except OSError as e:
        raise OutputError(f"{what}: cannot write in {folder}: {e.strerror or e}") from None


def check_file(target: str | Path, inputs: Iterable[str | Path | None] = ()) -> Path:
    """Check that ``target`` can be written as a file and is none of ``inputs``.

    Returns the target; raises :class:`OutputError` naming it and the rule.
    """
    target = Path(target)
    res = target.resolve()
    for p in _resolved(inputs):
        if res == p:
            raise OutputError(f"{target}: is an input of this command; write elsewhere")
    if target.is_dir():
        raise OutputError(f"{target}: is a folder; give a file name")
    if target.exists() and not os.access(target, os.W_OK):
        raise OutputError(f"{target}: exists and is not writable")
    _probe(res.parent, str(target))
    return target


def write_text(target: str | Path, text: str, inputs: Iterable[str | Path | None] = ()) -> Path:
    """Write ``text`` to ``target`` atomically (temporary file beside it, then rename)."""
    target = check_file(target, inputs)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.resolve().parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as f:
            f.write(text)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target


def is_ours(folder: str | Path) -> bool:
    """True when ``folder`` holds :data:`MARKER` (a folder feeddrive wrote)."""
    return (Path(folder) / MARKER).is_file()


def check_dir(target: str | Path, inputs: Iterable[str | Path | None] = (),
              force: bool = False) -> Path:
    """Check that ``target`` may receive one run's results (rules in the module docstring).

    Returns the target; raises :class:`OutputError` naming it and the rule.
    """
    target = Path(target)
    res = target.resolve()
    for p in _resolved(inputs):
        if _inside(p, res):
            raise OutputError(f"{target}: holds an input of this command ({p}); "
                              "its contents would be replaced: write elsewhere")
    if _inside(Path.cwd().resolve(), res):
        raise OutputError(f"{target}: holds the working directory; give a folder of its own")
    if target.exists():
        if not target.is_dir():
            raise OutputError(f"{target}: exists and is not a folder")
        if not force and not is_ours(target) and any(target.iterdir()):
            raise OutputError(f"{target}: is a non-empty folder not written by feeddrive "
                              f"(no {MARKER}); empty it, choose another, or give --force "
                              "to replace it")
    _probe(res.parent, str(target))
    return target


@contextmanager
def output_dir(target: str | Path, inputs: Iterable[str | Path | None] = (),
               force: bool = False, what: str = "feeddrive") -> Iterator[Path]:
    """A fresh temporary folder beside ``target`` to write into; moved into place on success.

    ``what`` is recorded in the marker file.  On an exception the temporary folder is
    removed and ``target`` keeps its previous contents.
    """
    target = check_dir(target, inputs, force)
    parent = target.resolve().parent
    stage = Path(tempfile.mkdtemp(prefix=f".{target.name}.new-", dir=parent))
    try:
        yield stage
        (stage / MARKER).write_text(json.dumps({"written_by": "feeddrive", "what": what}) + "\n",
                                    encoding="utf-8")
        old = None
        if target.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{target.name}.old-", dir=parent))
            os.replace(target, old / "d")
        try:
            os.replace(stage, target)
        except OSError:
            if old is not None:
                os.replace(old / "d", target)
            raise
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
    finally:
        if stage.exists():
            shutil.rmtree(stage, ignore_errors=True)
