"""The process's extractions of ``.fmu`` files: each file (same path, modification time and
size) is unpacked and its model description parsed once per process (:func:`unpacked`), its
libraries loaded once and held for the process, the folders removed at exit.

Every :class:`feeddrive.fmu.Plant` of one file shares the extraction; each still has its own
fmpy wrapper and FMI instance (``dlopen`` of the same file counts references, fmpy's
``freeInstance`` drops one, and the cache holds one for the process).
"""

from __future__ import annotations

import atexit
import ctypes
import os
import shutil
import tempfile
import threading
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from fmpy import extract, platform_tuple, read_model_description, sharedLibraryExtension
from fmpy import platform as fmpy_platform
from fmpy.model_description import ModelDescription, ScalarVariable

from . import fmu3


@dataclass(frozen=True)
class Unpacked:
    """One extraction of an ``.fmu``: its folder and parsed model description (shared, read-only)."""

    path: Path
    directory: str
    md: ModelDescription
    vars: Mapping[str, ScalarVariable]
    #: the process's own reference on the shared libraries: a Plant's ``freeInstance``
    #: (dlclose) never unloads a library other Plants use
    libraries: tuple[ctypes.CDLL, ...] = ()
    #: FMI 3.0: the model description at each configured friction.N (made on first use)
    dimensioned: dict[int, ModelDescription] = field(default_factory=dict)

    def with_n(self, n: int) -> ModelDescription:
        """The model description with arrays of ``friction.N = n`` elements (FMI 3.0; shared)."""
        md = self.dimensioned.get(n)
        if md is None:
            md = self.dimensioned[n] = fmu3.with_dimension(self.md, n)
        return md


class _ExtractionCache:
    """Extractions by (resolved path, mtime, size), made once per process, removed at exit."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._entries: dict[tuple[str, int, int], Unpacked] = {}
        self._owner = os.getpid()  # a forked child must not remove its parent's folders
        atexit.register(self.clear)

    def get(self, path: Path) -> Unpacked:
        st = path.stat()
        key = (str(path.resolve()), st.st_mtime_ns, st.st_size)
        with self._lock:
            hit = self._entries.get(key)
            if hit is None:
                md = read_model_description(str(path))
                directory = tempfile.mkdtemp(prefix="feeddrive_fmu_")
                extract(str(path), directory)
                ids = {i.modelIdentifier for i in (md.coSimulation, md.modelExchange) if i}
                plat = platform_tuple if md.fmiVersion.startswith("3") else fmpy_platform
                libs = tuple(
                    ctypes.CDLL(
                        os.path.join(directory, "binaries", plat, i + sharedLibraryExtension)
                    )
                    for i in sorted(ids)
                )
                hit = Unpacked(path, directory, md, {v.name: v for v in md.modelVariables}, libs)
                self._entries[key] = hit
            return hit

    def clear(self) -> None:
        """Remove the extractions (at exit; a Plant still open keeps its loaded library)."""
        with self._lock:
            entries, self._entries = self._entries, {}
        if os.getpid() == self._owner:
            for e in entries.values():
                shutil.rmtree(e.directory, ignore_errors=True)


_CACHE = _ExtractionCache()


def unpacked(path: str | Path) -> Unpacked:
    """The process's extraction of the ``.fmu`` at ``path`` (made on first use).

    A file changed since (another mtime or size) is extracted again; the previous
    extraction stays until exit for the Plants that use it.
    """
    return _CACHE.get(Path(path))
