"""Load the feed-drive FMU with fmpy, set parameters by name, and run it.

Two interfaces of the same ``.fmu``:

* ``"cs"`` (default): co-simulation; ``fmi2DoStep`` integrates with the FMU's own
  event-locating Dormand-Prince 5(4).  Fast path: :meth:`Plant.raw_calls`, our own ctypes
  handles on the library fmpy loaded, on pre-built arrays: three calls per controller sample.
* ``"me"``: model exchange integrated by fmpy's CVode (SUNDIALS) between samples, with the
  state events and time events handled here as FMI 2.0 prescribes.  The reference path.

The FMU file's ``fmiVersion`` picks the FMI version once, when a :class:`Plant` is made: the
calls that differ go through one adapter (:class:`feeddrive.fmu2.FMI2`, :class:`feeddrive.fmu3.FMI3`),
so an FMI 3.0 build (``LinearMotorFeedDrive3.fmu``) runs behind the same API (fmpy's
FMU3Slave / FMU3Model), FMI 2.0 names included: ``friction.F[3]`` is element 3 of the FMI 3.0 array ``friction.F``,
``friction.N`` is set in Configuration Mode (:mod:`feeddrive.fmu3`), and :meth:`Plant.raw_calls`
gives fmi3DoStep / fmi3GetFloat64 / fmi3SetFloat64 in the FMI 2.0 call shapes.

Every :class:`Plant` of one ``.fmu`` file in a process shares one extraction and one parsed
model description (:func:`feeddrive.fmu_extraction.unpacked`); each Plant still has its own
fmpy wrapper and FMI instance.
"""

from __future__ import annotations

import ctypes
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol, Self

import numpy as np
from fmpy.fmi2 import (
    fmi2Real,
    fmi2ValueReference,
)
from fmpy.model_description import ModelDescription, ScalarVariable

from . import fmu2, fmu3
from .fmu_extraction import Unpacked as Unpacked
from .fmu_extraction import unpacked as unpacked
from .model_description import DEFAULT_FMU as DEFAULT_FMU
from .model_description import FMU_ENV as FMU_ENV
from .model_description import FMUError as FMUError
from .model_description import FMUNotFoundError as FMUNotFoundError
from .model_description import fmi_version as fmi_version
from .model_description import fmu_path as fmu_path

OUTPUTS = ("x", "v", "a", "i", "F_motor", "F_cogging", "F_friction", "K_f")


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

    The calls that differ between FMI 2.0 and FMI 3.0 are made by one adapter chosen here
    from the file's ``fmiVersion`` (:class:`feeddrive.fmu2.FMI2`, :class:`feeddrive.fmu3.FMI3`).

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

    def __init__(
        self,
        parameters: Mapping[str, float | int | bool] | None = None,
        interface: str = "cs",
        tolerance: float = 1e-6,
        path: str | Path | None = None,
        log: bool = False,
    ) -> None:
        if interface not in ("cs", "me"):
            raise ValueError(f"interface = {interface!r}: allowed 'cs' or 'me'")
        self.path = fmu_path(path)
        self.interface = interface
        self.parameters = dict(parameters or {})
        self.tolerance = float(self.parameters.get("solver.tol", tolerance))
        shared = unpacked(self.path)
        self.fmi_version = fmi_version(self.path)
        self.messages: list[str] = []
        self._fmi: _Version = (
            fmu3.FMI3(self.path, shared, self.parameters, self.messages)
            if self.fmi_version.startswith("3")
            else fmu2.FMI2(self.path, shared, self.messages)
        )
        self.md = self._fmi.md
        self.vars = self._fmi.vars
        for name in self.parameters:
            if name not in self.vars and self._fmi.element(name) is None:
                raise KeyError(f"parameter {name!r} is not a variable of {self.path.name}")
        self._dir = shared.directory
        self._log = log
        self.fmu = self._fmi.wrapper_class(interface)(
            guid=self.md.guid,
            unzipDirectory=self._dir,
            modelIdentifier=self.md.coSimulation.modelIdentifier
            if interface == "cs"
            else self.md.modelExchange.modelIdentifier,
            instanceName="feeddrive",
        )
        self._fmi.fmu = self.fmu
        self._instantiated = False
        self.generation = 0  #: counts instances: +1 at every start() and close()

    # ------------------------------------------------------------------ helpers
    def vr(self, name: str) -> int:
        """Value reference of variable ``name`` (FMI 3.0: a scalar variable, not an element)."""
        try:
            return int(self.vars[name].valueReference)
        except KeyError:
            if self._fmi.element(name) is not None:
                raise KeyError(
                    f"{name!r} is an element of an FMI 3.0 array of {self.path.name}: "
                    "use get()/set()"
                ) from None
            raise KeyError(f"{name!r} is not a variable of {self.path.name}") from None

    def _check(self, ok: bool, what: str) -> None:
        if not ok:
            raise FMUError(
                f"{what} failed: " + (self.messages[-1] if self.messages else "no message")
            )

    def set(self, values: Mapping[str, float | int | bool]) -> None:
        """Set variables by name (parameters before initialisation, tunables and inputs later)."""
        self._fmi.set(values)

    def get(self, names: Sequence[str]) -> dict[str, float]:
        """Current values of variables by name."""
        return self._fmi.get(names)

    def start(
        self,
        start_values: Mapping[str, float] | None = None,
        t0: float = 0.0,
        stop_time: float | None = None,
    ) -> None:
        """Instantiate, set parameters and start values, initialise (time ``t0``)."""
        if self._instantiated:
            self._fmi.free()
        self.messages.clear()
        with self._refused("instantiating"):
            self._fmi.instantiate(self._log)
        self._instantiated = True
        self.generation += 1
        with self._refused("setting up the experiment"):
            self._fmi.prepare(self.tolerance, t0, stop_time)
        self.set(self.parameters)
        if start_values:
            self.set(start_values)
        with self._refused("initialising"):
            self._fmi.initialise(self.tolerance, t0, stop_time)
        self.time = t0

    @contextmanager
    def _refused(self, what: str) -> Iterator[None]:
        """Turn fmpy's bare exception for a refused FMI call into an :class:`FMUError` that
        names the step and carries the FMU's last message."""
        try:
            yield
        except FMUError:
            raise
        except Exception as e:  # fmpy raises Exception on fmi2Error / fmi3Error
            raise FMUError(
                f"{what} {self.path.name}: " + (self.messages[-1] if self.messages else str(e))
            ) from None

    def do_step(self, t: float, h: float) -> bool:
        """Co-simulation: one step [t, t + h] (fmi2DoStep / fmi3DoStep); True when the FMU
        asks for event handling (FMI 3.0 with event mode only; never here)."""
        try:
            return self._fmi.do_step(t, h)
        except Exception as e:
            raise FMUError(
                f"doStep at t = {t}: " + (self.messages[-1] if self.messages else str(e))
            ) from None

    def update_discrete_states(self) -> tuple[Any, ...]:
        """Model exchange, event mode: fmi2NewDiscreteStates / fmi3UpdateDiscreteStates as
        (update needed, terminate, nominals changed, states changed, next time defined, next time)."""
        return self._fmi.update_discrete_states()

    def derivatives(self) -> Callable[..., Any]:
        """Model exchange: fmpy's call that writes the state derivatives, ``f(dx, nx)``
        (fmi2GetDerivatives / fmi3GetContinuousStateDerivatives)."""
        return self._fmi.derivatives()

    def get_derivatives(self, dx: object, nx: int) -> None:
        """Model exchange: the state derivatives into ``dx`` (fmi2GetDerivatives /
        fmi3GetContinuousStateDerivatives)."""
        self._fmi.derivatives()(dx, nx)

    def get_state(self) -> object:
        """A copy of the instance's state (fmi2GetFMUstate / fmi3GetFMUState)."""
        return self._fmi.get_state()

    def set_state(self, state: object) -> None:
        """Restore a state of :meth:`get_state` or :meth:`deserialize_state`."""
        self._fmi.set_state(state)

    def serialize_state(self, state: object) -> bytes:
        """The FMU's serialised form of ``state`` (the same safe format in both versions)."""
        return self._fmi.serialize_state(state)

    def deserialize_state(self, blob: bytes) -> object:
        """A state from :meth:`serialize_state`'s bytes."""
        return self._fmi.deserialize_state(blob)

    def reset(self) -> None:
        """fmi2Reset / fmi3Reset: back to the instantiated state (parameters must be set
        again: call :meth:`start` to run again)."""
        self._fmi.reset()

    def close(self) -> None:
        """Free the instance and this Plant's hold on the library (fmpy's ``freeInstance``;
        the shared extraction stays for the process's other Plants)."""
        if self._instantiated:
            try:
                self.fmu.terminate()
            except Exception:
                pass
            self.fmu.freeInstance()  # fmi2FreeInstance, then dlclose
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
            handles = self._fmi.raw_handles()
            self._raw_handles = handles
        return RawCalls(self.fmu.component, *handles)

    def raw(self, names: Sequence[str]) -> RawIO:
        """Pre-built ctypes arrays for ``names`` (Real variables): ~1 µs get/set calls."""
        return RawIO(self, names)


class _Version(Protocol):
    """The FMI calls of a :class:`Plant` that differ between FMI 2.0 and FMI 3.0, chosen once
    when the Plant is made (:class:`feeddrive.fmu2.FMI2`; :class:`feeddrive.fmu3.FMI3`)."""

    @property
    def md(self) -> ModelDescription:
        """The model description (FMI 3.0: at the Plant's ``friction.N``)."""

    @property
    def vars(self) -> Mapping[str, ScalarVariable]:
        """The variables of :attr:`md` by name."""

    fmu: Any  #: fmpy's wrapper of the library, given by the Plant that made it

    def wrapper_class(self, interface: str) -> Any:
        """fmpy's wrapper class for ``interface`` (``"cs"``, ``"me"``)."""

    def element(self, name: str) -> tuple[ScalarVariable, int] | None:
        """(array variable, 1-based index) an FMI 2.0 element name stands for (FMI 3.0)."""

    def set(self, values: Mapping[str, float | int | bool]) -> None:
        """Set variables by name."""

    def get(self, names: Sequence[str]) -> dict[str, float]:
        """Current values of variables by name."""

    def free(self) -> None:
        """Free the instance (the library stays loaded)."""

    def instantiate(self, log: bool) -> None:
        """Make a new instance whose messages go to the Plant's list."""

    def prepare(self, tolerance: float, t0: float, stop_time: float | None) -> None:
        """What comes between instantiation and setting the parameters."""

    def initialise(self, tolerance: float, t0: float, stop_time: float | None) -> None:
        """Enter and leave Initialization Mode."""

    def do_step(self, t: float, h: float) -> bool:
        """One co-simulation step; True when the FMU asks for event handling."""

    def update_discrete_states(self) -> tuple[Any, ...]:
        """fmi2NewDiscreteStates / fmi3UpdateDiscreteStates."""

    def derivatives(self) -> Callable[..., Any]:
        """fmpy's call that writes the state derivatives (``f(dx, nx)``)."""

    def get_state(self) -> object:
        """fmi2GetFMUstate / fmi3GetFMUState."""

    def set_state(self, state: object) -> None:
        """fmi2SetFMUstate / fmi3SetFMUState."""

    def serialize_state(self, state: object) -> bytes:
        """fmi2SerializeFMUstate / fmi3SerializeFMUState."""

    def deserialize_state(self, blob: bytes) -> object:
        """fmi2DeSerializeFMUstate / fmi3DeserializeFMUState."""

    def reset(self) -> None:
        """fmi2Reset / fmi3Reset."""

    def raw_handles(self) -> tuple[Callable[..., int], ...]:
        """do_step, get_real, set_real on the library in the FMI 2.0 call shapes."""

    def check_raw(self, names: Sequence[str]) -> None:
        """KeyError naming a variable the raw calls cannot reach."""


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
        plant._fmi.check_raw(names)
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
            self.calls = self.plant.raw_calls()  # FMUError when the plant is closed
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
