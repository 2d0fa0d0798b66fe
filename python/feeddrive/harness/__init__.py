"""The closed-loop harness below every stage: references, the sensor model, the controller
registry, the FMU loop, the run maker, the sidecar schema and the checks of a measured run.

- :mod:`.references`: :class:`Reference` and its profiles, :func:`prbs`, :func:`reversals`;
- :mod:`.sensors`: :class:`Sensors` (scale quantum, current noise, seed);
- :mod:`.controllers`: spec <-> controller (``state_space``, ``pid``, ``pid_lead``,
  ``lti``: any linear digital controller), the registry; :mod:`.controller_specs` (the specs
  with defaults), :mod:`.spec_keys` (reading a spec), :mod:`.lti_realisation` (an ``lti``
  spec's matrices), :mod:`.controller_builders` (spec -> controller for each type);
- :mod:`.simulate`: :func:`simulate_open_loop`, :func:`simulate_closed_loop` on a Plant;
- :mod:`.runs`: :func:`run_closed_loop` from a spec, :func:`to_run`, :func:`closed_loop_run`;
- :mod:`.sidecar`: :func:`build_sidecar`, :func:`read_sidecar`, :func:`read_run_sidecar`
  (schema ``feeddrive.run/1``; any program's sidecar read for what it says);
- :mod:`.checked_runs`: :func:`~.checked_runs.check_run` (the refusals every command applies
  to a measured run), :func:`~.checked_runs.load_checked_runs` (a folder of runs, each checked);
- :mod:`.controller_fmu`: a spec -> the controller FMU's parameter set, :class:`ControllerFMU`;
- :mod:`.two_fmus`: the closed loop as controller FMU + plant FMU.
"""

from .controllers import (
    CONTROLLERS,
    Controller,
    cascade_lti_spec,
    controller_spec,
    lti_spec,
    make_controller,
    pid_lead_spec,
    pid_lti_spec,
    pid_spec,
    state_space_spec,
)
from .references import (
    Reference,
    back_and_forth,
    from_positions,
    point_to_point,
    prbs,
    reversals,
    sinusoid,
)
from .runs import SCALE_ONLY, closed_loop_run, run_closed_loop, to_run
from .sensors import IDEAL, Sensors
from .sidecar import SCHEMA, Sidecar, build_sidecar, read_run_sidecar, read_sidecar
from .simulate import RECORD, Stepper, quantise, simulate_closed_loop, simulate_open_loop

__all__ = [
    "CONTROLLERS",
    "Controller",
    "cascade_lti_spec",
    "controller_spec",
    "lti_spec",
    "make_controller",
    "pid_lead_spec",
    "pid_lti_spec",
    "pid_spec",
    "state_space_spec",
    "Reference",
    "back_and_forth",
    "from_positions",
    "point_to_point",
    "prbs",
    "reversals",
    "sinusoid",
    "SCALE_ONLY",
    "closed_loop_run",
    "run_closed_loop",
    "to_run",
    "IDEAL",
    "Sensors",
    "SCHEMA",
    "Sidecar",
    "build_sidecar",
    "read_run_sidecar",
    "read_sidecar",
    "RECORD",
    "Stepper",
    "quantise",
    "simulate_closed_loop",
    "simulate_open_loop",
]
