"""Load the feed-drive FMU with fmpy, set parameters by name, and run it.

Two interfaces of the same ``.fmu``:

* ``"cs"`` (default): co-simulation; ``fmi2DoStep`` integrates with the FMU's own
  event-locating Dormand-Prince 5(4).  Fast path: :meth:`Plant.raw_calls`, our own ctypes
  handles on the library fmpy loaded, on pre-built arrays: three calls per controller sample.
* ``"me"``: model exchange integrated by fmpy's CVode (SUNDIALS) between samples, with the
  state events and time events handled here as FMI 2.0 prescribes.  The reference path.

The FMU file's ``fmiVersion`` picks the FMI version: an FMI 3.0 build
(``LinearMotorFeedDrive3.fmu``) runs behind the same API (fmpy's FMU3Slave / FMU3Model),
FMI 2.0 names included: ``friction.F[3]`` is element 3 of the FMI 3.0 array ``friction.F``,
``friction.N`` is set in Configuration Mode (:mod:`feeddrive.fmu3`), and :meth:`Plant.raw_calls`
gives fmi3DoStep / fmi3GetFloat64 / fmi3SetFloat64 in the FMI 2.0 call shapes.

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
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Self

import numpy as np
from fmpy import extract, platform_tuple, read_model_description, sharedLibraryExtension
from fmpy import platform as fmpy_platform
from fmpy.fmi2 import (
    FMU2Model,
    FMU2Slave,
    defaultCallbacks,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2Real,
    fmi2ValueReference,
)
from fmpy.fmi3 import FMU3Model, FMU3Slave
from fmpy.model_description import ModelDescription, ScalarVariable

from . import fmu3

# re-exported: the names the package and its users take from here
from .model_description import DEFAULT_FMU as DEFAULT_FMU
from .model_description import FMU_ENV as FMU_ENV
from .model_description import FMUNotFoundError as FMUNotFoundError
from .model_description import fmi_version
from .model_description import fmu_path as fmu_path

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
                plat = platform_tuple if md.fmiVersion.startswith("3") else fmpy_platform
                libs = tuple(ctypes.CDLL(os.path.join(directory, "binaries", plat,
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
class Result(Mapping[str, np.ndarray]):
    """Recorded signals of one run: ``res["x"]`` etc. are numpy arrays over ``res["time"]``."""

    signals: dict[str, np.ndarray]

    def __getitem__(self, k: str) -> np.ndarray:
        return self.signals[k]

    def __iter__(self) -> Iterator[str]:
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
        An FMI 3.0 file is instantiated with ``friction.N`` from ``parameters`` (Configuration
        Mode); an FMI 2.0 slot past N (``friction.F[7]`` at N = 5) is dropped when set and
        reads 0 (the FMI 2.0 FMU's unused slots hold 0 too).
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
        self.fmi_version = fmi_version(self.path)
        self.fmi3 = self.fmi_version.startswith("3")
        if self.fmi3:
            n = self.parameters.get(fmu3.N_NAME, shared.vars[fmu3.N_NAME].start)
            try:
                self.md = shared.with_n(int(n) if not isinstance(n, bool) else n)
            except (TypeError, ValueError) as e:
                raise ValueError(f"{self.path.name}: {e}") from None
            self.vars: Mapping[str, ScalarVariable] = {v.name: v for v in self.md.modelVariables}
        else:
            self.md = shared.md
            self.vars = shared.vars
        for name in self.parameters:
            if name not in self.vars and self._element(name) is None:
                raise KeyError(f"parameter {name!r} is not a variable of {self.path.name}")
        self._dir = shared.directory
        self.messages: list[str] = []
        self._log = log
        self._arrays: dict[str, list[Any]] = {}      # FMI 3.0: array values set so far (before init)
        self._initialised = False
        if self.fmi3:
            cls = _Slave3 if interface == "cs" else _Model3
        else:
            cls = FMU2Slave if interface == "cs" else FMU2Model
        self.fmu = cls(guid=self.md.guid, unzipDirectory=self._dir,
                       modelIdentifier=self.md.coSimulation.modelIdentifier if interface == "cs"
                       else self.md.modelExchange.modelIdentifier,
                       instanceName="feeddrive")
        self._instantiated = False
        self.generation = 0     #: counts instances: +1 at every start() and close()

    # ------------------------------------------------------------------ helpers
    def vr(self, name: str) -> int:
        """Value reference of variable ``name`` (FMI 3.0: a scalar variable, not an element)."""
        try:
            return self.vars[name].valueReference
        except KeyError:
            if self._element(name) is not None:
                raise KeyError(f"{name!r} is an element of an FMI 3.0 array of {self.path.name}: "
                               "use get()/set()") from None
            raise KeyError(f"{name!r} is not a variable of {self.path.name}") from None

    def _element(self, name: str) -> tuple[ScalarVariable, int] | None:
        """FMI 3.0: (array variable, 1-based index) an FMI 2.0 element name stands for."""
        return fmu3.element(self.md, name) if self.fmi3 else None

    def _logger3(self, env: object, status: int, category: bytes | None,
                 message: bytes | str) -> None:  # fmpy's FMI 3.0 callback
        self._logger(env, None, status, category, message)

    def _logger(self, env: object, name: bytes | None, status: int, category: bytes | None,
                message: bytes | str) -> None:  # fmpy callback
        text = message.decode() if isinstance(message, bytes) else str(message)
        self.messages.append(text)

    def _check(self, ok: bool, what: str) -> None:
        if not ok:
            raise FMUError(f"{what} failed: " + (self.messages[-1] if self.messages else "no message"))

    def set(self, values: Mapping[str, float | int | bool]) -> None:
        """Set variables by name (parameters before initialisation, tunables and inputs later)."""
        if self.fmi3:
            self._set3(values)
            return
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

    def _array3(self, var: ScalarVariable) -> list[Any]:
        """FMI 3.0: the current values of array ``var``: the FMU's (before initialisation
        the values set so far, else its defaults: the model description lists start values for
        the default N only; the FMU has defaults for all ten slots, as the FMI 2.0 one)."""
        n = int(np.prod(var.shape))
        get = getattr(self.fmu, "get" + var.type)
        if self._initialised:
            return list(get([var.valueReference], nValues=n))
        if var.name not in self._arrays:
            start = [var._python_type(x) for x in str(var.start).split()] if var.start is not None else []
            if len(start) < n:
                try:
                    start = list(get([var.valueReference], nValues=n))
                except Exception:
                    raise FMUError(f"{var.name}: no start values for friction.N = {n} elements "
                                   "(set all of them)") from None
            self._arrays[var.name] = start[:n]
        return self._arrays[var.name]

    def _set3(self, values: Mapping[str, float | int | bool]) -> None:
        for name, value in values.items():
            var = self.vars.get(name)
            index = None
            if var is None:
                hit = self._element(name)
                if hit is None:
                    raise KeyError(f"{name!r} is not a variable of {self.path.name}")
                var, index = hit
            if name == fmu3.N_NAME:
                if int(value) != int(var.start):
                    raise FMUError(f"setting {name} = {value!r}: the FMI 3.0 instance was configured "
                                   f"with {var.start} (a structural parameter: pass it to Plant)")
                continue
            if index is None:
                vals = list(value) if isinstance(value, (list, tuple, np.ndarray)) else [value]
            else:
                vals = self._array3(var)
                if index > len(vals):
                    continue              # an FMI 2.0 slot past friction.N: no element here
                vals[index - 1] = var._python_type(value)
            try:
                getattr(self.fmu, "set" + var.type)([var.valueReference],
                                                    [var._python_type(x) for x in vals])
            except Exception as e:  # fmpy raises on fmi3Error
                raise FMUError(f"setting {name} = {value!r}: "
                               + (self.messages[-1] if self.messages else str(e))) from None

    def _get3(self, names: Sequence[str]) -> dict[str, float]:
        out = {}
        for name in names:
            var = self.vars.get(name)
            if var is not None and not var.dimensions:
                out[name] = getattr(self.fmu, "get" + var.type)([var.valueReference])[0]
                continue
            hit = self._element(name)
            if hit is None:
                raise KeyError(f"{name!r} is not a variable of {self.path.name}")
            var, index = hit
            n = int(np.prod(var.shape))
            out[name] = (getattr(self.fmu, "get" + var.type)([var.valueReference], nValues=n)[index - 1]
                         if index <= n else var._python_type(0))
        return out

    def get(self, names: Sequence[str]) -> dict[str, float]:
        """Current values of variables by name."""
        if self.fmi3:
            return self._get3(names)
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
        if self.fmi3:
            self._start3(start_values, t0, stop_time)
            return
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

    def _start3(self, start_values: Mapping[str, float] | None, t0: float,
                stop_time: float | None) -> None:
        if self._instantiated:
            self.fmu.fmi3FreeInstance(self.fmu.component)
        self.messages.clear()
        self._initialised = False
        self._arrays = {}
        self.fmu.instantiate(loggingOn=self._log, logMessage=self._logger3)
        self._instantiated = True
        self.generation += 1
        nvar = self.vars[fmu3.N_NAME]
        if int(nvar.start) != int(unpacked(self.path).vars[fmu3.N_NAME].start):
            self.fmu.enterConfigurationMode()
            self.fmu.setInt32([nvar.valueReference], [int(nvar.start)])
            self.fmu.exitConfigurationMode()
        self.set(self.parameters)
        if start_values:
            self.set(start_values)
        try:
            self.fmu.enterInitializationMode(tolerance=self.tolerance, startTime=t0, stopTime=stop_time)
            self.fmu.exitInitializationMode()
        except Exception:
            raise FMUError("initialisation failed: " + (self.messages[-1] if self.messages else "")) from None
        self._initialised = True
        self._arrays = {}
        self.time = t0

    # ------------------------------------------------------------------ either version
    def do_step(self, t: float, h: float) -> bool:
        """Co-simulation: one step [t, t + h] (fmi2DoStep / fmi3DoStep); True when the FMU
        asks for event handling (FMI 3.0 with event mode only; never here)."""
        try:
            if self.fmi3:
                return bool(self.fmu.doStep(t, h)[0])
            self.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        except Exception as e:
            raise FMUError(f"doStep at t = {t}: " + (self.messages[-1] if self.messages else str(e))) from None
        return False

    def update_discrete_states(self) -> tuple[Any, ...]:
        """Model exchange, event mode: fmi2NewDiscreteStates / fmi3UpdateDiscreteStates as
        (update needed, terminate, nominals changed, states changed, next time defined, next time)."""
        return self.fmu.updateDiscreteStates() if self.fmi3 else self.fmu.newDiscreteStates()

    def get_derivatives(self, dx: object, nx: int) -> None:
        """Model exchange: the state derivatives into ``dx`` (fmi2GetDerivatives /
        fmi3GetContinuousStateDerivatives)."""
        if self.fmi3:
            self.fmu.getContinuousStateDerivatives(dx, nx)
        else:
            self.fmu.getDerivatives(dx, nx)

    def get_state(self) -> object:
        """A copy of the instance's state (fmi2GetFMUstate / fmi3GetFMUState)."""
        return self.fmu.getFMUState() if self.fmi3 else self.fmu.getFMUstate()

    def set_state(self, state: object) -> None:
        """Restore a state of :meth:`get_state` or :meth:`deserialize_state`."""
        if self.fmi3:
            self.fmu.setFMUState(state)
        else:
            self.fmu.setFMUstate(state)

    def serialize_state(self, state: object) -> bytes:
        """The FMU's serialised form of ``state`` (the same safe format in both versions)."""
        return self.fmu.serializeFMUState(state) if self.fmi3 else self.fmu.serializeFMUstate(state)

    def deserialize_state(self, blob: bytes) -> object:
        """A state from :meth:`serialize_state`'s bytes."""
        return self.fmu.deserializeFMUState(blob) if self.fmi3 else self.fmu.deSerializeFMUstate(blob)

    def reset(self) -> None:
        """fmi2Reset / fmi3Reset: back to the instantiated state (parameters must be set
        again: call :meth:`start` to run again)."""
        self.fmu.reset()
        self._initialised = False
        self._arrays = {}

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

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:
            pass

    # ------------------------------------------------------------------ fast raw access
    def raw_calls(self) -> RawCalls:
        """Own ctypes handles on the started instance's fmi2DoStep, fmi2GetReal, fmi2SetReal.

        Loaded from the FMU's shared library (fmpy's public ``dll``), independent of fmpy's
        wrappers; pointer arguments are addresses (int) or ctypes arrays.  Valid until the
        next :meth:`start` or :meth:`close`.
        """
        if not self._instantiated:
            raise FMUError("raw_calls: the FMU instance is not started (call start() first)")
        handles = self.__dict__.get("_raw_handles")
        if handles is None:
            handles = fmu3.raw_handles3(self.fmu.dll) if self.fmi3 else _load_raw_handles(self.fmu.dll)
            self._raw_handles = handles
        return RawCalls(self.fmu.component, *handles)

    def raw(self, names: Sequence[str]) -> RawIO:
        """Pre-built ctypes arrays for ``names`` (Real variables): ~1 µs get/set calls."""
        return RawIO(self, names)


#: fmpy's FMI 3.0 function table of each library, shared by the Plants that load it (fmpy
#: makes ~80 ctypes functions per instance otherwise: ~60 KiB a Plant).  The library stays
#: loaded for the process (:class:`Unpacked` holds a reference), so the pointers stay valid.
_FMI3_FUNCTIONS: dict[tuple[str, str], dict[str, Any]] = {}


class _SharedFunctions:
    """Mixin: one fmpy function table per (interface, library) instead of one per instance."""

    dll: ctypes.CDLL
    _functions: dict[str, Any]

    def _loadFunctions(self) -> None:
        key = (type(self).__mro__[2].__name__, self.dll._name)
        table = _FMI3_FUNCTIONS.get(key)
        if table is None:
            super()._loadFunctions()  # type: ignore[misc]  # fmpy's class after the mixin has it
            _FMI3_FUNCTIONS[key] = self._functions
        else:
            self._functions = table


class _Slave3(_SharedFunctions, FMU3Slave):  # type: ignore[misc]  # fmpy has no type information
    """fmpy's FMU3Slave on the shared function table."""


class _Model3(_SharedFunctions, FMU3Model):  # type: ignore[misc]  # fmpy has no type information
    """fmpy's FMU3Model on the shared function table."""


def _load_raw_handles(dll: ctypes.CDLL) -> tuple[Callable[..., int], ...]:
    """fmi2DoStep, fmi2GetReal, fmi2SetReal of ``dll`` with our own ctypes signatures."""
    ptr, n = ctypes.c_void_p, ctypes.c_size_t
    sigs: tuple[tuple[str, list[Any]], ...] = (
            ("fmi2DoStep", [ptr, ctypes.c_double, ctypes.c_double, ctypes.c_int]),
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
        if plant.fmi3:
            for s in names:
                if plant.vars.get(s) is None or plant.vars[s].type != "Float64" or plant.vars[s].dimensions:
                    raise KeyError(f"raw: {s!r} is not a scalar Float64 variable of {plant.path.name}")
        self.vr = (fmi2ValueReference * n)(*[plant.vr(s) for s in names])
        self.vr_address = ctypes.addressof(self.vr)
        self.buf = (fmi2Real * n)()
        self.np = np.ctypeslib.as_array(self.buf)
        self.calls = plant.raw_calls()
        self._generation = plant.generation

    def _current(self) -> RawCalls:
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
