"""The campaign as a plan: the limits checked, the controller chosen, the runs built."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, cast

from ...effects import Experiment, experiments, resolve
from ...model_file import ModelFile
from .builder import PlanBuilder
from .controller import check_controller, default_controller
from .limits import Limits, check_limits
from .runs import Plan


def make_plan(
    model: ModelFile, limits: Limits, controller: Mapping[str, Any] | str | None = "default"
) -> Plan:
    """The campaign sized to ``limits`` on the nominal ``model`` (its Ts, mass, friction and
    force constant size the runs).

    ``controller`` is the drive's controller as a registry spec
    (:mod:`feeddrive.harness.controllers`), written into every closed-loop sidecar: "default"
    is :func:`default_controller`; None writes null (not described); a type the registry
    does not know is kept as written, with a note.  PlanError
    naming the option for limits the campaign cannot fit.
    """
    params = model.fmu_parameters()
    check_limits(limits, params)
    Ts = float(params["Ts"])
    notes: list[str] = []
    if isinstance(controller, str):
        if controller != "default":
            raise ValueError(
                f"make_plan: controller {controller!r}: give a spec, None or 'default'"
            )
        spec = default_controller(params, limits.u_limit)
    elif controller is None:
        spec = None
        notes.append(
            "no controller described (controller null in the sidecars): a "
            "closed-loop replay (validate) of the recordings is skipped"
        )
    else:
        spec = check_controller(controller, Ts, notes)
    plan = Plan(model_name=model.name, limits=limits, Ts=Ts, controller=spec, notes=notes)
    b = PlanBuilder(plan, params)
    for exp in experiments():
        cast(Callable[[PlanBuilder, Experiment], None], resolve(exp.plan))(b, exp)
    return plan
