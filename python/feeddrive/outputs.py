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

The one guard, :func:`check_not_input`, compares an output with everything the command
reads (a :class:`Reads`: each run CSV and its sidecar path, model, study and FMU files, and
folders read as a whole), by real path (symbolic links resolved) and by file identity (a hard
link): a file output is none of them, a folder output holds none of them, and neither lies
inside a folder read as a whole.  A symbolic link loop is refused, and so is an existing
output that is not a regular file.  The command line runs it for every output option of
every command before the command starts; :func:`check_file` and :func:`check_dir` run it too.

Every refusal is an :class:`OutputError` (a ValueError) naming the path and the rule.
"""

from __future__ import annotations

import errno
import json
import os
import secrets
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from .data import RUN_SUFFIXES, sidecar_path

#: the file that marks a folder as written by feeddrive
MARKER = ".feeddrive-output"


class OutputError(ValueError):
    """An output path that cannot or must not be written; names the path and the rule."""


def _inside(path: Path, folder: Path) -> bool:
    return path == folder or folder in path.parents


def _real(path: str | Path) -> Path:
    """The absolute path with every symbolic link resolved (a loop stays unresolved)."""
    return Path(os.path.realpath(path))


@dataclass(frozen=True)
class Reads:
    """What a command reads: ``files`` as (path, how it is read: "" or "the sidecar of X, ")
    and ``trees``, folders read as a whole (nothing may be written inside them)."""

    files: tuple[tuple[Path, str], ...] = ()
    trees: tuple[Path, ...] = ()

    @classmethod
    def of(
        cls,
        files: Iterable[str | Path | None] = (),
        runs: Iterable[str | Path | None] = (),
        run_folders: Iterable[str | Path | None] = (),
        trees: Iterable[str | Path | None] = (),
    ) -> Reads:
        """The files and folders given, each run CSV with its sidecar path (whether or not the
        sidecar exists: a file written there would become one), every ``*.csv`` and ``*.csv.gz`` of each run
        folder with its sidecar path (and the folder itself)."""
        items = [(Path(f), "") for f in files if f is not None]
        csvs = [Path(r) for r in runs if r is not None]
        for folder in (Path(d) for d in run_folders if d is not None):
            items.append((folder, ""))
            if folder.is_dir():
                csvs += sorted({p for end in RUN_SUFFIXES for p in folder.glob(f"*{end}")})
        for run in csvs:
            items += [(run, ""), (sidecar_path(run), f"the sidecar of {run}, ")]
        return cls(tuple(items), tuple(Path(t) for t in trees if t is not None))

    def __add__(self, other: Reads) -> Reads:
        return Reads(self.files + other.files, self.trees + other.trees)


def _reads(inputs: Reads | Iterable[str | Path | None]) -> Reads:
    return inputs if isinstance(inputs, Reads) else Reads.of(files=inputs)


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def check_not_input(
    target: str | Path, inputs: Reads | Iterable[str | Path | None], folder: bool
) -> Path:
    """The guard of every output: raise :class:`OutputError` when writing the file (or, with
    ``folder``, replacing the folder) ``target`` could change something the command reads
    (rules in the module docstring).  Returns ``target``'s real path."""
    target = Path(target)
    try:
        mode: int | None = os.stat(target).st_mode
    except OSError as e:
        if e.errno == errno.ELOOP:
            raise OutputError(
                f"{target}: is a symbolic link loop; give a path that resolves"
            ) from None
        mode = None  # missing, or a folder that cannot be made: the caller says which
    if mode is not None and not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):
        raise OutputError(
            f"{target}: exists and is neither a regular file nor a folder "
            "(a FIFO, a device, a socket); write elsewhere"
        )
    res = _real(target)
    reads = _reads(inputs)
    for path, how in reads.files:
        real = _real(path)
        if res == real or _same_file(target, path):
            raise OutputError(f"{target}: is {how}an input of this command; write elsewhere")
        if folder and _inside(real, res):
            raise OutputError(
                f"{target}: holds an input of this command ({path}); "
                "its contents would be replaced: write elsewhere"
            )
    for tree in reads.trees:
        real = _real(tree)
        if _inside(res, real):
            raise OutputError(
                f"{target}: is inside {tree}, a folder this command reads; write elsewhere"
            )
        if folder and _inside(real, res):
            raise OutputError(
                f"{target}: holds {tree}, a folder this command reads; write elsewhere"
            )
    return res


def _probe(folder: Path, what: str) -> None:
    """Create ``folder`` (and parents) and write a temporary file in it."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(prefix=".feeddrive-probe-", dir=folder)
        os.close(fd)
        os.unlink(name)
    except OSError as e:
        raise OutputError(f"{what}: cannot write in {folder}: {e.strerror or e}") from None


def check_file(target: str | Path, inputs: Reads | Iterable[str | Path | None] = ()) -> Path:
    """Check that ``target`` can be written as a file and is none of ``inputs``
    (:func:`check_not_input`: paths, or a :class:`Reads`).

    Returns the target; raises :class:`OutputError` naming it and the rule.
    """
    target = Path(target)
    res = check_not_input(target, inputs, folder=False)
    if target.is_dir():
        raise OutputError(f"{target}: is a folder; give a file name")
    if target.exists() and not os.access(target, os.W_OK):
        raise OutputError(f"{target}: exists and is not writable")
    _probe(res.parent, str(target))
    return target


def _temporary_beside(target: Path) -> tuple[int, Path]:
    """A new file beside ``target`` (created with mode 0666 less the umask, like ``open``)."""
    parent = _real(target).parent
    while True:
        tmp = parent / f".{target.name[:120]}.{secrets.token_hex(6)}.tmp"
        try:
            return os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666), tmp
        except FileExistsError:
            continue


def write_with(
    target: str | Path,
    write: Callable[[Path], object],
    inputs: Reads | Iterable[str | Path | None] = (),
) -> Path:
    """Write ``target`` atomically through ``write(tmp)``, which fills the temporary file
    ``tmp`` beside it (then renamed over ``target``: a reader sees the old or the new file);
    a file replaced keeps its permission bits, a new one gets those of ``open`` (0666 less the
    umask).  On an exception the temporary file is removed and ``target`` is untouched."""
    target = check_file(target, inputs)
    fd, tmp = _temporary_beside(target)
    try:
        try:
            os.chmod(fd, stat.S_IMODE(os.stat(target).st_mode))
        except FileNotFoundError:
            pass
        os.close(fd)
        write(tmp)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target


def write_text(
    target: str | Path, text: str, inputs: Reads | Iterable[str | Path | None] = ()
) -> Path:
    """Write ``text`` to ``target`` atomically (:func:`write_with`)."""

    def write(tmp: Path) -> None:
        with open(tmp, "w", encoding="utf-8", newline="") as f:
            f.write(text)

    return write_with(target, write, inputs)


def is_ours(folder: str | Path) -> bool:
    """True when ``folder`` holds :data:`MARKER` (a folder feeddrive wrote)."""
    return (Path(folder) / MARKER).is_file()


def check_dir(
    target: str | Path, inputs: Reads | Iterable[str | Path | None] = (), force: bool = False
) -> Path:
    """Check that ``target`` may receive one run's results (rules in the module docstring;
    ``inputs``: paths, or a :class:`Reads`).

    Returns the target; raises :class:`OutputError` naming it and the rule.
    """
    target = Path(target)
    res = check_not_input(target, inputs, folder=True)
    if _inside(Path.cwd().resolve(), res):
        raise OutputError(f"{target}: holds the working directory; give a folder of its own")
    if target.exists():
        if not target.is_dir():
            raise OutputError(f"{target}: exists and is not a folder")
        if not force and not is_ours(target) and any(target.iterdir()):
            raise OutputError(
                f"{target}: is a non-empty folder not written by feeddrive "
                f"(no {MARKER}); empty it, choose another, or give --force "
                "to replace it"
            )
    _probe(res.parent, str(target))
    return target


def _stage_dir(target: Path) -> Path:
    """A new folder beside ``target`` with ``target``'s permission bits when it is a folder,
    else those of ``mkdir`` (0777 less the umask)."""
    parent = _real(target).parent
    while True:
        stage = parent / f".{target.name[:120]}.new-{secrets.token_hex(6)}"
        try:
            os.mkdir(stage, 0o777)
            break
        except FileExistsError:
            continue
    if target.is_dir():
        os.chmod(stage, stat.S_IMODE(os.stat(target).st_mode))
    return stage


@contextmanager
def output_dir(
    target: str | Path,
    inputs: Reads | Iterable[str | Path | None] = (),
    force: bool = False,
    what: str = "feeddrive",
) -> Iterator[Path]:
    """A fresh temporary folder beside ``target`` to write into; moved into place on success.

    ``what`` is recorded in the marker file.  On an exception the temporary folder is
    removed and ``target`` keeps its previous contents.
    """
    target = check_dir(target, inputs, force)
    parent = _real(target).parent
    stage = _stage_dir(target)
    try:
        yield stage
        (stage / MARKER).write_text(
            json.dumps({"written_by": "feeddrive", "what": what}) + "\n", encoding="utf-8"
        )
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
