"""Load the feed-drive FMU with fmpy, set parameters by name, and run it.

Two interfaces of the same ``.fmu``:

* ``"cs"`` (default): co-simulation; ``fmi2DoStep`` integrates with the FMU's own
  event-locating Dormand-Prince 5(4).  Fast path: :meth:`Plant.raw_calls`, our own ctypes
  handles on the library fmpy loaded, on pre-built arrays: three calls per controller sample.
* ``"me"``: model exchange integrated by fmpy's CVode (SUNDIALS) between samples, with the
  state events and time events handled here as FMI 2.0 prescribes.  The reference path.

Every :class:`Plant` of one ``.fmu`` file (same path, same modification time and size) in a
process shares one extraction and one parsed model description (:func:`unpacked`); each Plant
still has its own fmpy wrapper and FMI instance (the library is loaded once: ``dlopen`` of
the same file counts references, fmpy's ``freeInstance`` drops one, and the cache holds one
for the process).  The extractions are
removed when the process that made them exits.
"""
from __future__ import annotations

import atexit
import ctypes
import os
import shutil
import tempfile
import threading
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description, sharedLibraryExtension
from fmpy import platform as fmpy_platform
from fmpy.model_description import ModelDescription, ScalarVariable
from fmpy.fmi2 import (FMU2Model, FMU2Slave, defaultCallbacks, fmi2CallbackFunctions,
                       fmi2CallbackLoggerTYPE, fmi2Real, fmi2ValueReference)

from .model_description import DEFAULT_FMU, FMU_ENV, FMUNotFoundError, fmu_path  # noqa: F401

OUTPUTS = ("x", "v", "a", "i", "F_motor", "F_cogging", "F_friction", "K_f")


class FMUError(RuntimeError):
    """An FMI call failed; the message carries what the FMU logged."""


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


class _ExtractionCache:
    """Extractions by (resolved path, mtime, size), made once per process, removed at exit."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._entries: dict[tuple[str, int, int], Unpacked] = {}
        self._owner = os.getpid()      # a forked child must not remove its parent's folders
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
                libs = tuple(ctypes.CDLL(os.path.join(directory, "binaries", fmpy_platform,
                                                      i + sharedLibraryExtension))
                             for i in sorted(ids))
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


@dataclass
class Result(Mapping):
    """Recorded signals of one run: ``res["x"]`` etc. are numpy arrays over ``res["time"]``."""

    signals: dict[str, np.ndarray]

    def __getitem__(self, k: str) -> np.ndarray:
        return self.signals[k]

    def __iter__(self):
        return iter(self.signals)

    def __len__(self) -> int:
        return len(self.signals)


class Plant:
    """One FMU instance of the feed drive.

    Parameters
    ----------
    parameters : FMU parameter values by name (SI), e.g. from
        :meth:`feeddrive.model_file.ModelFile.fmu_parameters`; unspecified ones keep the
        FMU's defaults (the paper's model).
    interface : ``"cs"`` or ``"me"``.
    tolerance : relative tolerance of the integrator (CS: the FMU's DP45; ME: CVode); a
        ``solver.tol`` in ``parameters`` takes its place (it is passed as the experiment's
        tolerance, which the FMU would otherwise use instead of ``solver.tol``).
    path : the ``.fmu``; default ``$FEEDDRIVE_FMU``, else the package's copy (:func:`fmu_path`).
    """

    def __init__(self, parameters: Mapping[str, float | int | bool] | None = None,
                 interface: str = "cs", tolerance: float = 1e-6,
                 path: str | Path | None = None, log: bool = False) -> None:
        if interface not in ("cs", "me"):
            raise ValueError(f"interface = {interface!r}: allowed 'cs' or 'me'")
        self.path = fmu_path(path)
        self.interface = interface
        self.parameters = dict(parameters or {})
        self.tolerance = float(self.parameters.get("solver.tol", tolerance))
        shared = unpacked(self.path)
        self.md = shared.md
        self.vars = shared.vars
        for name in self.parameters:
            if name not in self.vars:
                raise KeyError(f"parameter {name!r} is not a variable of {self.path.name}")
        self._dir = shared.directory
        self.messages: list[str] = []
        self._log = log
        cls = FMU2Slave if interface == "cs" else FMU2Model
        self.fmu = cls(guid=self.md.guid, unzipDirectory=self._dir,
                       modelIdentifier=self.md.coSimulation.modelIdentifier if interface == "cs"
                       else self.md.modelExchange.modelIdentifier,
                       instanceName="feeddrive")
        self._instantiated = False
        self.generation = 0     #: counts instances: +1 at every start() and close()

    # ------------------------------------------------------------------ helpers
    def vr(self, name: str) -> int:
        """Value reference of variable ``name``."""
        try:
            return self.vars[name].valueReference
        except KeyError:
            raise KeyError(f"{name!r} is not a variable of {self.path.name}") from None

    def _logger(self, env, name, status, category, message):  # fmpy callback
        text = message.decode() if isinstance(message, bytes) else str(message)
        self.messages.append(text)

    def _check(self, ok: bool, what: str) -> None:
        if not ok:
            raise FMUError(f"{what} failed: " + (self.messages[-1] if self.messages else "no message"))

    def set(self, values: Mapping[str, float | int | bool]) -> None:
        """Set variables by name (parameters before initialisation, tunables and inputs later)."""
        for name, value in values.items():
            v = self.vars.get(name)
            if v is None:
                raise KeyError(f"{name!r} is not a variable of {self.path.name}")
            try:
                if v.type == "Real":
                    self.fmu.setReal([v.valueReference], [float(value)])
                elif v.type == "Integer":
                    self.fmu.setInteger([v.valueReference], [int(value)])
                elif v.type == "Boolean":
                    self.fmu.setBoolean([v.valueReference], [bool(value)])
            except Exception as e:  # fmpy raises on fmi2Error
                raise FMUError(f"setting {name} = {value!r}: "
                               + (self.messages[-1] if self.messages else str(e))) from None

    def get(self, names: Sequence[str]) -> dict[str, float]:
        """Current values of variables by name."""
        out = {}
        for name in names:
            v = self.vars[name]
            if v.type == "Real":
                out[name] = self.fmu.getReal([v.valueReference])[0]
            elif v.type == "Integer":
                out[name] = self.fmu.getInteger([v.valueReference])[0]
            else:
                out[name] = self.fmu.getBoolean([v.valueReference])[0]
        return out

    def start(self, start_values: Mapping[str, float] | None = None, t0: float = 0.0,
              stop_time: float | None = None) -> None:
        """Instantiate, set parameters and start values, initialise (time ``t0``)."""
        if self._instantiated:
            self.fmu.fmi2FreeInstance(self.fmu.component)
        self.messages.clear()
        cb = fmi2CallbackFunctions()
        self._logger_c = fmi2CallbackLoggerTYPE(self._logger)   # kept alive with the instance
        cb.logger = self._logger_c
        cb.allocateMemory = defaultCallbacks.allocateMemory
        cb.freeMemory = defaultCallbacks.freeMemory
        self._callbacks = cb
        self.fmu.instantiate(loggingOn=self._log, callbacks=cb)
        self._instantiated = True
        self.generation += 1
        self.fmu.setupExperiment(tolerance=self.tolerance, startTime=t0, stopTime=stop_time)
        self.set(self.parameters)
        if start_values:
            self.set(start_values)
        self.fmu.enterInitializationMode()
        try:
            self.fmu.exitInitializationMode()
        except Exception:
            raise FMUError("initialisation failed: " + (self.messages[-1] if self.messages else "")) from None
        self.time = t0

    def close(self) -> None:
        """Free the instance and this Plant's hold on the library (fmpy's ``freeInstance``;
        the shared extraction stays for the process's other Plants)."""
        if self._instantiated:
            try:
                self.fmu.terminate()
            except Exception:
                pass
            self.fmu.freeInstance()            # fmi2FreeInstance, then dlclose
            self._instantiated = False
            self.generation += 1

    def __enter__(self) -> "Plant":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:
            pass

    # ------------------------------------------------------------------ fast raw access
    def raw_calls(self) -> "RawCalls":
        """Own ctypes handles on the started instance's fmi2DoStep, fmi2GetReal, fmi2SetReal.

        Loaded from the FMU's shared library (fmpy's public ``dll``), independent of fmpy's
        wrappers; pointer arguments are addresses (int) or ctypes arrays.  Valid until the
        next :meth:`start` or :meth:`close`.
        """
        if not self._instantiated:
            raise FMUError("raw_calls: the FMU instance is not started (call start() first)")
        handles = self.__dict__.get("_raw_handles")
        if handles is None:
            handles = _load_raw_handles(self.fmu.dll)
            self._raw_handles = handles
        return RawCalls(self.fmu.component, *handles)

    def raw(self, names: Sequence[str]) -> "RawIO":
        """Pre-built ctypes arrays for ``names`` (Real variables): ~1 µs get/set calls."""
        return RawIO(self, names)


def _load_raw_handles(dll: ctypes.CDLL) -> tuple[Callable[..., int], ...]:
    """fmi2DoStep, fmi2GetReal, fmi2SetReal of ``dll`` with our own ctypes signatures."""
    ptr, n = ctypes.c_void_p, ctypes.c_size_t
    sigs = (("fmi2DoStep", [ptr, ctypes.c_double, ctypes.c_double, ctypes.c_int]),
            ("fmi2GetReal", [ptr, ptr, n, ptr]), ("fmi2SetReal", [ptr, ptr, n, ptr]))
    out = []
    for name, argtypes in sigs:
        f = dll[name]            # a new function object: fmpy's own handle is left alone
        f.restype = ctypes.c_int
        f.argtypes = argtypes
        out.append(f)
    return tuple(out)


@dataclass(frozen=True)
class RawCalls:
    """The three FMI calls of the 2 kHz loop, bound to one instance.

    Each returns the fmi2Status (> 1: fmi2Discard or worse).

    - ``do_step(component, t, h, 1)``: fmi2DoStep;
    - ``get_real(component, vr, n, values)`` / ``set_real(component, vr, n, values)``:
      ``vr`` an array of n fmi2ValueReference, ``values`` of n fmi2Real (addresses or arrays).
    """

    component: int
    do_step: Callable[..., int]
    get_real: Callable[..., int]
    set_real: Callable[..., int]


class RawIO:
    """Get/set a fixed list of Real variables with pre-built arrays (the 2 kHz fast path).

    Attributes ``vr`` / ``buf`` (ctypes arrays), ``vr_address`` (int) and ``calls``
    (:class:`RawCalls`) let a loop make the calls itself.
    """

    def __init__(self, plant: Plant, names: Sequence[str]) -> None:
        n = len(names)
        self.plant = plant
        self.names = list(names)
        self.n = n
        self.vr = (fmi2ValueReference * n)(*[plant.vr(s) for s in names])
        self.vr_address = ctypes.addressof(self.vr)
        self.buf = (fmi2Real * n)()
        self.np = np.ctypeslib.as_array(self.buf)
        self.calls = plant.raw_calls()
        self._generation = plant.generation

    def _current(self) -> "RawCalls":
        """The calls on the plant's current instance: after a restart the arrays are re-bound
        to the new instance (never a freed one); after close() an FMUError."""
        if self._generation != self.plant.generation:
            self.calls = self.plant.raw_calls()      # FMUError when the plant is closed
            self._generation = self.plant.generation
        return self.calls

    def fail(self, what: str) -> None:
        """Raise FMUError for a failed ``what`` on these variables, with the FMU's message."""
        msgs = self.plant.messages
        raise FMUError(f"{what} {', '.join(self.names)}: " + (msgs[-1] if msgs else "no message"))

    def get(self) -> np.ndarray:
        """Current values (a view on the buffer: copy it to keep it)."""
        c = self._current()
        if c.get_real(c.component, self.vr, self.n, self.buf) > 1:
            self.fail("fmi2GetReal")
        return self.np

    def get_into(self, address: int) -> None:
        """Write the current values to ``n`` doubles at ``address`` (no copy)."""
        c = self._current()
        if c.get_real(c.component, self.vr_address, self.n, address) > 1:
            self.fail("fmi2GetReal")

    def set(self, values: Sequence[float]) -> None:
        """Set the values; FMUError (with the FMU's message naming variable, value and range)
        when the FMU rejects them."""
        for k, v in enumerate(values):
            self.buf[k] = v
        c = self._current()
        if c.set_real(c.component, self.vr, self.n, self.buf) > 1:
            self.fail("fmi2SetReal")
