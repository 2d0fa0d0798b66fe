"""Compile FMU-named parameters into typed, frozen plant parameters, with the rules and
messages of the FMU (fmu_src/models/plant/params.c and the effect
entries of fmu_src/physics/, in the effect table's order).

:func:`compile` takes a model (anything with ``fmu_parameters()``, e.g. a
:class:`feeddrive.model_file.ModelFile`) or a mapping of FMU parameter names to values
(missing names keep the FMU's defaults, the paper's values, as an FMU instance does), checks
every rule of the FMU in its order and applies the effect switches once:

- single values (``params_check_value``; the FMU checks them on fmi2Set*, logging
  ``"fmi2SetReal: " + message``): every parameter finite; m, Ts, F_s, V_s, delta, C, k_i,
  lambda_j in (0, inf); F_c, sigma2 in [0, inf); nu_i in [0, 1]; N in [1, 10]; then the
  ``min``/``max`` that modelDescription.xml declares (read from the FMU's own file by
  :mod:`feeddrive.model_description`), the interval that keeps the arithmetic finite;
- the compiled set (``plant_params_compile``; the FMU checks it when initialisation ends or a
  tunable changes, logging the message itself): the rules the effect modules own
  (:func:`feeddrive.effects.broken_rule`: every effect's ``compile_rule``, then every
  ``check_rule``, in catalogue order, as the FMU's effect table): sum(current.a) != 1,
  x_max > x_min, F_c <= F_s, with asymmetry the levels and viscous coefficient for v < 0
  non-negative, N an integer, with pre-rolling |sum(nu_1..N) - 1| <= 1e-3,
  friction_profile.x_end > friction_profile.x_start and friction_profile.n an integer (the
  knot values' range [-0.9, 4] is the XML's and keeps p(x) >= 0.1).

The structural switches (the current loop's dynamics, the GMS elements, the level profile,
the load on a spring) reach the compiled types through the structure each effect declares
(:class:`feeddrive.effects.Structure`); the others act through their ``off`` rules
(:func:`feeddrive.effects.apply_switches`).

A broken rule raises :class:`ParameterError` whose message is the FMU's, byte for byte.
"""

from __future__ import annotations

import math
import types
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike

from ..effects import Structure, apply_switches, broken_rule, structure_on, switchable
from ..model_description import Variable, variables
from ..paper import N_ELEMENTS_MAX, paper_parameters
from .compliance import Compliance
from .current_loop import CurrentLoop
from .friction_gms import GMSParameters
from .position_maps import MAP_EFFECTS, PositionMap

#: FMU parameters of the integrator, not of the plant (checked for finiteness only).
SOLVER_PARAMETERS = ("solver.tol", "solver.fast")


class ParameterError(ValueError):
    """A parameter set the FMU refuses; the message is the one the FMU logs."""


class HasFmuParameters(Protocol):
    def fmu_parameters(self) -> Mapping[str, Any]: ...


# range rules: (lo, lo_open, hi, hi_open), as params.c range_of and the effects' range entries
_POS = (0.0, True, math.inf, True)
_NONNEG = (0.0, False, math.inf, True)
_UNIT = (0.0, False, 1.0, False)
_NEL = (1.0, False, float(N_ELEMENTS_MAX), False)


def _range_of(name: str) -> tuple[float, bool, float, bool] | None:
    if name in ("m", "Ts", "friction.F_s", "friction.V_s", "friction.delta", "friction.C"):
        return _POS
    if name in ("friction.F_c", "friction.sigma2"):
        return _NONNEG
    if name == "friction.N":
        return _NEL
    base = name.split("[")[0]
    if base == "friction.nu":
        return _UNIT
    if base in ("friction.k", "cogging.lambda", "ripple.lambda"):
        return _POS
    return None


def _num(v: float) -> str:
    """effects.c effect_num(): %.15g when it reads back exactly, else %.17g."""
    s = f"{v:.15g}"
    return s if float(s) == v else f"{v:.17g}"


def _bound(v: float) -> str:
    """An interval end as params.c prints it."""
    return ("-inf" if v < 0 else "inf") if math.isinf(v) else _num(v)


def _g(v: float) -> str:
    """C's %g of a non-finite double (glibc prints the sign of a NaN)."""
    if math.isnan(v):
        return "-nan" if math.copysign(1.0, v) < 0 else "nan"
    return f"{v:g}"


def check_value(name: str, value: float, declared: Mapping[str, Variable] | None = None) -> None:
    """One parameter alone (params.c ``plant_check_value``); ParameterError if refused.

    ``declared``: the FMU's variables (:func:`variables`), read here when not given (a caller
    that checks many values reads them once)."""
    v = float(value)
    var = (variables() if declared is None else declared).get(name)
    unit = var.unit if var is not None else ""  # as modelDescription.xml declares it
    if not math.isfinite(v):
        raise ParameterError(
            f"{name} = {_g(v)} is not a finite number: allowed values are "
            f"finite{' [' + unit + ']' if unit else ''}"
        )
    r = _range_of(name)
    if r is not None:
        lo, lo_open, hi, hi_open = r
        if (v <= lo if lo_open else v < lo) or (v >= hi if hi_open else v > hi):
            rs = f"{'(' if lo_open else '['}{_bound(lo)}, {_bound(hi)}{')' if hi_open else ']'}"
            raise ParameterError(f"{name} = {_num(v)} is out of range: allowed {rs} {unit}")
    if var is not None and not var.lo <= v <= var.hi:
        raise ParameterError(
            f"{name} = {_num(v)} is out of range: allowed "
            f"[{_bound(var.lo)}, {_bound(var.hi)}] {unit}"
        )


@dataclass(frozen=True)
class PlantParameters:
    """The plant's parameters with the effect switches applied (SI), as params.c's
    ``plant_params_t``.

    ``friction`` holds the GMS elements i <= N with nu_i > 0; with ``prerolling`` off the
    plant uses the static friction of :mod:`.friction_static` with the same levels.
    ``values`` are every FMU parameter by name (as given, switches included).
    """

    m: float
    Ts: float
    current: CurrentLoop
    cogging: PositionMap
    ripple: PositionMap
    x_min: float
    x_max: float
    friction: GMSParameters
    prerolling: bool
    F_offset: float
    values: Mapping[str, Any]
    compliance: Compliance  #: the load on its spring-damper (effect compliance)

    def K_f(self, x: ArrayLike) -> np.ndarray:
        """K_f(x) [N/A] at x clamped to the stroke (Eq. 7, plant.c)."""
        return self.ripple(np.clip(np.asarray(x, dtype=float), self.x_min, self.x_max))

    def F_cg(self, x: ArrayLike) -> np.ndarray:
        """F_cg(x) [N] at x clamped to the stroke (Eq. 6, plant.c)."""
        return self.cogging(np.clip(np.asarray(x, dtype=float), self.x_min, self.x_max))


def parameter_values(model: HasFmuParameters | Mapping[str, Any]) -> dict[str, Any]:
    """Every FMU parameter by name: the FMU's defaults (the paper's) updated with ``model``'s."""
    given = model.fmu_parameters() if hasattr(model, "fmu_parameters") else model
    values: dict[str, Any] = paper_parameters()
    values.update(given)
    return values


def compile(model: HasFmuParameters | Mapping[str, Any]) -> PlantParameters:
    """Check ``model``'s parameters as the FMU does and compile them (module docstring).

    Raises
    ------
    ParameterError : the first rule broken, with the FMU's message.
    KeyError : a name that is not an FMU parameter.
    """
    val = parameter_values(model)
    known = paper_parameters()
    for name in val:
        if name not in known and name not in SOLVER_PARAMETERS:
            raise KeyError(f"{name!r} is not a parameter of the FMU")
    declared = variables()
    for name, v in val.items():
        check_value(name, v, declared)
    msg = broken_rule(val)  # plant_params_compile's rules, the effect table's order
    if msg is not None:
        raise ParameterError(msg)
    on = {e.id: bool(val[e.switch]) for e in switchable() if e.switch is not None}
    maps = {
        name: PositionMap.from_parameters(name, val, on[per], on[aper])
        for name, (per, aper) in MAP_EFFECTS.items()
    }
    return PlantParameters(
        m=float(val["m"]),
        Ts=float(val["Ts"]),
        current=CurrentLoop.from_parameters(val),
        cogging=maps["cogging"],
        ripple=maps["ripple"],
        x_min=float(val["stroke.x_min"]),
        x_max=float(val["stroke.x_max"]),
        friction=GMSParameters.from_params(val),
        prerolling=structure_on(val, Structure.SLIP_ELEMENTS),
        F_offset=float(apply_switches(val)["offset.F"]),
        values=types.MappingProxyType(val),
        compliance=Compliance.from_parameters(val),
    )
