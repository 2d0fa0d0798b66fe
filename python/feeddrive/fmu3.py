"""The plant as an FMI 3.0 FMU (``LinearMotorFeedDrive3.fmu``) under fmpy, any ``friction.N``.

The FMI 3.0 FMU has the same physics and variables as the FMI 2.0 one; the GMS element
forces, their rates, ``friction.nu``, ``friction.k`` and the stuck flags are arrays whose
dimension is the structural parameter ``friction.N`` (set in Configuration Mode only, as the
standard and the Reference FMUs do).  fmpy sizes arrays and the state vector from the start
values of the model description and never enters Configuration Mode, so ``fmpy.simulate_fmu``
runs the FMU as it is at its default ``friction.N``; for another N, :func:`configured` makes the
instance and the model description that ``simulate_fmu(..., model_description=md,
fmu_instance=fmu)`` then runs.
"""

from __future__ import annotations

import copy
import ctypes
import re
from collections.abc import Callable, Mapping, Sequence
from importlib import resources
from pathlib import Path
from typing import Any, Protocol

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Model, FMU3Slave
from fmpy.model_description import ModelDescription, ModelVariable

from .model_description import FMUError

DEFAULT_FMU3 = Path(str(resources.files(__package__) / "LinearMotorFeedDrive3.fmu"))
N_NAME = "friction.N"
N_MAX = 10
INTERFACES = ("ModelExchange", "CoSimulation")
#: an FMI 2.0 element name: friction.F[3], der(friction.F[3])
_ELEMENT = re.compile(r"(der\()?(.+)\[(\d+)\]\)?")


def with_dimension(md: ModelDescription, n: int) -> ModelDescription:
    """A copy of ``md`` whose arrays of dimension ``friction.N`` have ``n`` elements.

    Raises ValueError naming friction.N, the value and the allowed range.
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= int(n) <= N_MAX:
        raise ValueError(f"{N_NAME} = {n!r}: allowed an integer in [1, {N_MAX}]")
    md = copy.deepcopy(md)
    var = next(v for v in md.modelVariables if v.name == N_NAME)
    var.start = str(int(n))
    for v in md.modelVariables:
        if v.dimensions:
            v.shape = tuple(
                int(n) if d.valueReference == var.valueReference else int(d.start)
                for d in v.dimensions
            )
            if v.start is not None and len(str(v.start).split()) > 1:
                v.start = " ".join(str(v.start).split()[: int(np.prod(v.shape))])
    md.numberOfContinuousStates = sum(int(np.prod(u.variable.shape)) for u in md.derivatives)
    return md


def configured(
    path: str | Path, interface: str, n: int, **instantiate: object
) -> tuple[ModelDescription, FMU3Model | FMU3Slave]:
    """An instance of the FMI 3.0 FMU at ``path`` with ``friction.N = n`` (state Instantiated)
    and its model description, for ``fmpy.simulate_fmu(path, model_description=md,
    fmu_instance=fmu)``.  ``instantiate``: fmpy's instantiate() arguments (``logMessage``,
    ``eventModeUsed``, ``earlyReturnAllowed``, ...).

    The friction parameters ``friction.nu`` / ``friction.k`` must then be set with ``n``
    values each (their sum rule is checked at initialisation).  Raises ValueError for a bad
    ``interface`` or ``n`` (naming it, its value and the allowed ones).
    """
    if interface not in INTERFACES:
        raise ValueError(f"interface = {interface!r}: allowed {', '.join(INTERFACES)}")
    md = with_dimension(read_model_description(str(path)), n)
    cls = FMU3Model if interface == "ModelExchange" else FMU3Slave
    mi = md.modelExchange if interface == "ModelExchange" else md.coSimulation
    fmu = cls(
        guid=md.guid,
        unzipDirectory=extract(str(path)),
        modelIdentifier=mi.modelIdentifier,
        instanceName="feeddrive",
    )
    fmu.instantiate(**instantiate)
    vr = next(v.valueReference for v in md.modelVariables if v.name == N_NAME)
    fmu.enterConfigurationMode()
    fmu.setInt32([vr], [int(n)])
    fmu.exitConfigurationMode()
    return md, fmu


def fmi3_values(
    md: ModelDescription, values: dict[str, float | int | bool]
) -> dict[str, float | int | bool | list[Any]]:
    """FMI 2.0 names and values (``friction.nu[2]``, ...) as the FMI 3.0 variables of ``md``:
    the elements of an array of dimension N gathered into one list (elements not given keep
    their start values; elements past N are dropped: they do not act on the model).  Raises
    KeyError naming a variable neither version has."""
    by_name = {v.name: v for v in md.modelVariables}
    out: dict[str, float | int | bool | list[Any]] = {}
    for name, value in values.items():
        if name in by_name:
            out[name] = value
            continue
        base, _, idx = name.rpartition("[")
        var = by_name.get(base)
        if var is None or not var.dimensions or not idx.endswith("]"):
            raise KeyError(f"{name}: no such variable in the FMI 3.0 model description")
        k = int(idx[:-1])
        n = int(np.prod(var.shape))
        if k > n:
            continue
        cur = out.get(base)
        if not isinstance(cur, list):
            cur = out[base] = (
                [var._python_type(s) for s in str(var.start).split()]
                if var.start
                else [var._python_type(0)] * n
            )
        cur[k - 1] = value
    return out


def set_values(
    fmu: FMU3Model | FMU3Slave, md: ModelDescription, values: dict[str, float | int | bool]
) -> None:
    """Set ``values`` (FMI 2.0 or FMI 3.0 names, :func:`fmi3_values`) on ``fmu`` by type;
    ``friction.N`` must equal the instance's (it is set in Configuration Mode, :func:`configured`)."""
    by_name = {v.name: v for v in md.modelVariables}
    for name, value in fmi3_values(md, values).items():
        var = by_name[name]
        if name == N_NAME:
            if isinstance(value, list) or int(value) != int(var.start):
                raise ValueError(
                    f"{N_NAME} = {value}: this instance was configured with {var.start} "
                    "(use configured(path, interface, N))"
                )
            continue
        vals = list(value) if isinstance(value, list) else [value]
        getattr(fmu, "set" + var.type)([var.valueReference], [var._python_type(x) for x in vals])


def element(md: ModelDescription, name: str) -> tuple[ModelVariable, int] | None:
    """The FMI 3.0 array variable of ``md`` and the 1-based index that the FMI 2.0 scalar
    ``name`` (``friction.F[3]``, ``der(friction.F[3])``) stands for; None when ``name`` is
    not an element name of an array of ``md``.  The index may exceed the array's size
    (``friction.N`` < 10): such an FMI 2.0 slot has no counterpart in the FMI 3.0 instance."""
    m = _ELEMENT.fullmatch(name)
    if m is None:
        return None
    base = f"der({m.group(2)})" if m.group(1) else m.group(2)
    for v in md.modelVariables:
        if v.name == base and v.dimensions:
            return v, int(m.group(3))
    return None


def raw_handles3(dll: ctypes.CDLL) -> tuple[Callable[..., int], ...]:
    """fmi3DoStep, fmi3GetFloat64, fmi3SetFloat64 of ``dll`` behind the FMI 2.0 call shapes
    of :class:`feeddrive.fmu.RawCalls`: ``do_step(c, t, h, flag)``, ``get_real(c, vr, n,
    values)`` / ``set_real(c, vr, n, values)`` on n scalar Float64 variables (nValues = n)."""
    ptr, n, dbl, b = ctypes.c_void_p, ctypes.c_size_t, ctypes.c_double, ctypes.c_bool
    do = dll["fmi3DoStep"]
    do.restype = ctypes.c_int
    do.argtypes = [ptr, dbl, dbl, b, ptr, ptr, ptr, ptr]
    flags = (b * 3)()
    last = dbl()
    a_event, a_term, a_early = (ctypes.addressof(flags) + k for k in range(3))
    a_last = ctypes.addressof(last)
    get, set_ = dll["fmi3GetFloat64"], dll["fmi3SetFloat64"]
    for f in (get, set_):
        f.restype = ctypes.c_int
        f.argtypes = [ptr, ptr, n, ptr, n]

    def do_step(
        c: int, t: float, h: float, no_set_prior: int, _keep: object = (flags, last)
    ) -> int:
        # _keep: the output buffers live as long as the function (their addresses are passed)
        return do(c, t, h, bool(no_set_prior), a_event, a_term, a_early, a_last)

    def get_real(c: int, vr: object, k: int, values: object) -> int:
        return get(c, vr, k, values, k)

    def set_real(c: int, vr: object, k: int, values: object) -> int:
        return set_(c, vr, k, values, k)

    return do_step, get_real, set_real


class Extraction(Protocol):
    """What the FMI 3.0 calls need of an ``.fmu``'s extraction (:class:`feeddrive.fmu.Unpacked`)."""

    @property
    def vars(self) -> Mapping[str, ModelVariable]:
        """The variables of the model description as the file has it, by name."""

    def with_n(self, n: int) -> ModelDescription:
        """The model description with arrays of ``friction.N = n`` elements."""


class FMI3:
    """FMI 3.0 behind :class:`feeddrive.fmu.Plant`: fmpy's FMU3Slave / FMU3Model, the instance
    configured with the Plant's ``friction.N``; FMI 2.0 element names (``friction.F[3]``)
    reach the elements of the FMI 3.0 arrays."""

    def __init__(
        self,
        path: Path,
        shared: Extraction,
        parameters: Mapping[str, float | int | bool],
        messages: list[str],
    ) -> None:
        self.path = path
        self.messages = messages
        self._default_n = int(shared.vars[N_NAME].start)
        n = parameters.get(N_NAME, shared.vars[N_NAME].start)
        try:
            self.md = shared.with_n(int(n) if not isinstance(n, bool) else n)
        except (TypeError, ValueError) as e:
            raise ValueError(f"{path.name}: {e}") from None
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.fmu: Any = None
        self._arrays: dict[str, list[Any]] = {}  # array values set so far (before initialisation)
        self._initialised = False

    def wrapper_class(self, interface: str) -> Any:
        return _Slave3 if interface == "cs" else _Model3

    def _logger(
        self, env: object, status: object, category: object, message: object
    ) -> None:  # fmpy's FMI 3.0 callback
        self.messages.append(message.decode() if isinstance(message, bytes) else str(message))

    def element(self, name: str) -> tuple[ModelVariable, int] | None:
        return element(self.md, name)

    def _array(self, var: ModelVariable) -> list[Any]:
        """The current values of array ``var``: the FMU's (before initialisation the values
        set so far, else its defaults: the model description lists start values for the
        default N only; the FMU has defaults for all ten slots, as the FMI 2.0 one)."""
        n = int(np.prod(var.shape))
        get = getattr(self.fmu, "get" + var.type)
        if self._initialised:
            return list(get([var.valueReference], nValues=n))
        if var.name not in self._arrays:
            start = (
                [var._python_type(x) for x in str(var.start).split()]
                if var.start is not None
                else []
            )
            if len(start) < n:
                try:
                    start = list(get([var.valueReference], nValues=n))
                except Exception:
                    raise FMUError(
                        f"{var.name}: no start values for friction.N = {n} elements "
                        "(set all of them)"
                    ) from None
            self._arrays[var.name] = start[:n]
        return self._arrays[var.name]

    def set(self, values: Mapping[str, float | int | bool]) -> None:
        for name, value in values.items():
            var = self.vars.get(name)
            index = None
            if var is None:
                hit = self.element(name)
                if hit is None:
                    raise KeyError(f"{name!r} is not a variable of {self.path.name}")
                var, index = hit
            if name == N_NAME:
                if int(value) != int(var.start):
                    raise FMUError(
                        f"setting {name} = {value!r}: the FMI 3.0 instance was configured "
                        f"with {var.start} (a structural parameter: pass it to Plant)"
                    )
                continue
            if index is None:
                vals = list(value) if isinstance(value, (list, tuple, np.ndarray)) else [value]
            else:
                vals = self._array(var)
                if index > len(vals):
                    continue  # an FMI 2.0 slot past friction.N: no element here
                vals[index - 1] = var._python_type(value)
            try:
                getattr(self.fmu, "set" + var.type)(
                    [var.valueReference], [var._python_type(x) for x in vals]
                )
            except Exception as e:  # fmpy raises on fmi3Error
                raise FMUError(
                    f"setting {name} = {value!r}: "
                    + (self.messages[-1] if self.messages else str(e))
                ) from None

    def get(self, names: Sequence[str]) -> dict[str, float]:
        out = {}
        for name in names:
            var = self.vars.get(name)
            if var is not None and not var.dimensions:
                out[name] = getattr(self.fmu, "get" + var.type)([var.valueReference])[0]
                continue
            hit = self.element(name)
            if hit is None:
                raise KeyError(f"{name!r} is not a variable of {self.path.name}")
            var, index = hit
            n = int(np.prod(var.shape))
            out[name] = (
                getattr(self.fmu, "get" + var.type)([var.valueReference], nValues=n)[index - 1]
                if index <= n
                else var._python_type(0)
            )
        return out

    def free(self) -> None:
        self.fmu.fmi3FreeInstance(self.fmu.component)

    def instantiate(self, log: bool) -> None:
        self._initialised = False
        self._arrays = {}
        self.fmu.instantiate(loggingOn=log, logMessage=self._logger)

    def prepare(self, tolerance: float, t0: float, stop_time: float | None) -> None:
        nvar = self.vars[N_NAME]
        if int(nvar.start) != self._default_n:
            self.fmu.enterConfigurationMode()
            self.fmu.setInt32([nvar.valueReference], [int(nvar.start)])
            self.fmu.exitConfigurationMode()

    def initialise(self, tolerance: float, t0: float, stop_time: float | None) -> None:
        try:
            self.fmu.enterInitializationMode(tolerance=tolerance, startTime=t0, stopTime=stop_time)
            self.fmu.exitInitializationMode()
        except Exception:
            raise FMUError(
                "initialisation failed: " + (self.messages[-1] if self.messages else "")
            ) from None
        self._initialised = True
        self._arrays = {}

    def do_step(self, t: float, h: float) -> bool:
        return bool(self.fmu.doStep(t, h)[0])

    def update_discrete_states(self) -> tuple[Any, ...]:
        out: tuple[Any, ...] = self.fmu.updateDiscreteStates()
        return out

    def derivatives(self) -> Callable[..., Any]:
        f: Callable[..., Any] = self.fmu.getContinuousStateDerivatives
        return f

    def get_state(self) -> object:
        return self.fmu.getFMUState()

    def set_state(self, state: object) -> None:
        self.fmu.setFMUState(state)

    def serialize_state(self, state: object) -> bytes:
        blob: bytes = self.fmu.serializeFMUState(state)
        return blob

    def deserialize_state(self, blob: bytes) -> object:
        return self.fmu.deserializeFMUState(blob)

    def reset(self) -> None:
        self.fmu.reset()
        self._initialised = False
        self._arrays = {}

    def raw_handles(self) -> tuple[Callable[..., int], ...]:
        return raw_handles3(self.fmu.dll)

    def check_raw(self, names: Sequence[str]) -> None:
        for s in names:
            var = self.vars.get(s)
            if var is None or var.type != "Float64" or var.dimensions:
                raise KeyError(f"raw: {s!r} is not a scalar Float64 variable of {self.path.name}")


#: fmpy's FMI 3.0 function table of each library, shared by the Plants that load it (fmpy
#: makes ~80 ctypes functions per instance otherwise: ~60 KiB a Plant).  The library stays
#: loaded for the process (:class:`feeddrive.fmu.Unpacked` holds a reference), so the
#: pointers stay valid.
_FMI3_FUNCTIONS: dict[tuple[str, str], dict[str, Any]] = {}


class _SharedFunctions:
    """Mixin: one fmpy function table per (interface, library) instead of one per instance."""

    _functions: dict[str, Any]
    dll: ctypes.CDLL

    def _loadFunctions(self) -> None:
        key = (type(self).__mro__[2].__name__, self.dll._name)
        table = _FMI3_FUNCTIONS.get(key)
        if table is None:
            super()._loadFunctions()  # type: ignore[misc]
            _FMI3_FUNCTIONS[key] = self._functions
        else:
            self._functions = table


class _Slave3(_SharedFunctions, FMU3Slave):  # type: ignore[misc]  # fmpy has no type information
    """fmpy's FMU3Slave on the shared function table."""


class _Model3(_SharedFunctions, FMU3Model):  # type: ignore[misc]  # fmpy has no type information
    """fmpy's FMU3Model on the shared function table."""
