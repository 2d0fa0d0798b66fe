"""FMI 2.0 behind :class:`feeddrive.fmu.Plant`: fmpy's FMU2Slave / FMU2Model, every name a
scalar (:class:`FMI2`; the FMI 3.0 adapter is :class:`feeddrive.fmu3.FMI3`), and our own ctypes
handles on the three calls of the fast loop (:func:`load_raw_handles`)."""

from __future__ import annotations

import ctypes
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from fmpy.fmi2 import (
    FMU2Model,
    FMU2Slave,
    defaultCallbacks,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)
from fmpy.model_description import ScalarVariable

from .fmu_extraction import Unpacked
from .model_description import FMUError


class FMI2:
    """FMI 2.0 behind :class:`Plant`: fmpy's FMU2Slave / FMU2Model, every name a scalar."""

    def __init__(self, path: Path, shared: Unpacked, messages: list[str]) -> None:
        self.path = path
        self.md = shared.md
        self.vars = shared.vars
        self.messages = messages
        self.fmu: Any = None

    def wrapper_class(self, interface: str) -> Any:
        return FMU2Slave if interface == "cs" else FMU2Model

    def _logger(
        self, env: object, name: object, status: object, category: object, message: object
    ) -> None:  # fmpy callback
        self.messages.append(message.decode() if isinstance(message, bytes) else str(message))

    def element(self, name: str) -> tuple[ScalarVariable, int] | None:
        return None

    def set(self, values: Mapping[str, float | int | bool]) -> None:
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
                raise FMUError(
                    f"setting {name} = {value!r}: "
                    + (self.messages[-1] if self.messages else str(e))
                ) from None

    def get(self, names: Sequence[str]) -> dict[str, float]:
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

    def free(self) -> None:
        self.fmu.fmi2FreeInstance(self.fmu.component)

    def instantiate(self, log: bool) -> None:
        cb = fmi2CallbackFunctions()
        self._logger_c = fmi2CallbackLoggerTYPE(self._logger)  # kept alive with the instance
        cb.logger = self._logger_c
        cb.allocateMemory = defaultCallbacks.allocateMemory
        cb.freeMemory = defaultCallbacks.freeMemory
        self._callbacks = cb
        self.fmu.instantiate(loggingOn=log, callbacks=cb)

    def prepare(self, tolerance: float, t0: float, stop_time: float | None) -> None:
        self.fmu.setupExperiment(tolerance=tolerance, startTime=t0, stopTime=stop_time)

    def initialise(self, tolerance: float, t0: float, stop_time: float | None) -> None:
        self.fmu.enterInitializationMode()
        try:
            self.fmu.exitInitializationMode()
        except Exception:
            raise FMUError(
                "initialisation failed: " + (self.messages[-1] if self.messages else "")
            ) from None

    def do_step(self, t: float, h: float) -> bool:
        self.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        return False

    def update_discrete_states(self) -> tuple[Any, ...]:
        out: tuple[Any, ...] = self.fmu.newDiscreteStates()
        return out

    def derivatives(self) -> Callable[..., Any]:
        f: Callable[..., Any] = self.fmu.getDerivatives
        return f

    def get_state(self) -> object:
        return self.fmu.getFMUstate()

    def set_state(self, state: object) -> None:
        self.fmu.setFMUstate(state)

    def serialize_state(self, state: object) -> bytes:
        blob: bytes = self.fmu.serializeFMUstate(state)
        return blob

    def deserialize_state(self, blob: bytes) -> object:
        return self.fmu.deSerializeFMUstate(blob)

    def reset(self) -> None:
        self.fmu.reset()

    def raw_handles(self) -> tuple[Callable[..., int], ...]:
        return load_raw_handles(self.fmu.dll)

    def check_raw(self, names: Sequence[str]) -> None:
        return None


def load_raw_handles(dll: ctypes.CDLL) -> tuple[Callable[..., int], ...]:
    """fmi2DoStep, fmi2GetReal, fmi2SetReal of ``dll`` with our own ctypes signatures."""
    ptr, n = ctypes.c_void_p, ctypes.c_size_t
    sigs: tuple[tuple[str, list[Any]], ...] = (
        ("fmi2DoStep", [ptr, ctypes.c_double, ctypes.c_double, ctypes.c_int]),
        ("fmi2GetReal", [ptr, ptr, n, ptr]),
        ("fmi2SetReal", [ptr, ptr, n, ptr]),
    )
    out = []
    for name, argtypes in sigs:
        f = dll[name]  # a new function object: fmpy's own handle is left alone
        f.restype = ctypes.c_int
        f.argtypes = argtypes
        out.append(f)
    return tuple(out)
