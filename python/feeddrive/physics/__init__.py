"""The plant's physics in Python, one concept per module, named as the C files of fmu_src/:

- :mod:`.params` (params.c): :func:`compile` -> :class:`PlantParameters`, the rules and
  messages of the FMU (:class:`ParameterError`);
- :mod:`.position_maps` (position_maps.c): K_f(x), F_cg(x) (Eqs. 6-7);
- :mod:`.friction_curves` (``friction_level`` of friction_levels.c): Stribeck curve, Eq. 12;
- :mod:`.friction_gms` (friction_gms.c): the GMS along a motion (Eqs. 8-11);
- :mod:`.gms_start`: the GMS element forces at a recording's first sample, estimated from
  Eq. 1's residual over the samples before every element has slipped;
- :mod:`.friction_static` (friction_static.c): Eq. 12 with Karnopp stiction;
- :mod:`.friction_position` (friction_position.c): the level profile p(x) of
  ``position_friction``;
- :mod:`.current_loop` (current_loop.c): G(z) of Eq. 2;
- :mod:`.compliance` (compliance.c): the load on a spring-damper (effect ``compliance``);
- :mod:`.plant` (plant.c): Eq. 1 on measured data (held current, run load, residual).

Identification, diagnosis and feedforward use only this package.

The effect switches reach the physics through the registry (:mod:`feeddrive.effects`), never by
name: the values of each switched-off effect's ``off`` rule (``apply_switches``), the plant
structure each structural effect selects (``structure_on`` with a
:class:`~feeddrive.effects.Structure`) and the rules each effect owns (``broken_rule``).
"""

from .compliance import Compliance, load_acceleration, load_filter, load_free_response
from .current_loop import (
    CurrentLoop,
    current_loop_dc_gain,
    current_loop_polynomials,
    simulate_current,
)
from .friction_curves import FrictionCurve, steady_friction, stribeck_drop, stribeck_level
from .friction_gms import GMSFriction, GMSParameters, element_forces, element_rates, gms_force
from .friction_position import FrictionProfile, profile_basis
from .friction_static import DEFAULT_V_STICK, karnopp_friction
from .gms_start import GMSStart, initial_elements, memory_wiped, started_friction
from .params import ParameterError, PlantParameters, check_value, compile, parameter_values
from .plant import (
    CURRENT_TIMINGS,
    FRICTION_VELOCITY_S,
    applied_force,
    eq1_friction,
    eq1_terms,
    force_residual,
    friction_velocity,
    held_current,
    measured_motion,
    run_load,
    run_load_mean,
)
from .position_maps import MapSpec, PositionMap, eval_map

__all__ = [
    "Compliance",
    "load_acceleration",
    "load_filter",
    "load_free_response",
    "CurrentLoop",
    "current_loop_dc_gain",
    "current_loop_polynomials",
    "simulate_current",
    "FrictionCurve",
    "steady_friction",
    "stribeck_drop",
    "stribeck_level",
    "FrictionProfile",
    "profile_basis",
    "GMSFriction",
    "GMSParameters",
    "element_forces",
    "element_rates",
    "gms_force",
    "DEFAULT_V_STICK",
    "karnopp_friction",
    "ParameterError",
    "PlantParameters",
    "check_value",
    "compile",
    "parameter_values",
    "CURRENT_TIMINGS",
    "applied_force",
    "eq1_friction",
    "eq1_terms",
    "force_residual",
    "held_current",
    "measured_motion",
    "FRICTION_VELOCITY_S",
    "friction_velocity",
    "GMSStart",
    "initial_elements",
    "memory_wiped",
    "started_friction",
    "run_load",
    "run_load_mean",
    "MapSpec",
    "PositionMap",
    "eval_map",
]
