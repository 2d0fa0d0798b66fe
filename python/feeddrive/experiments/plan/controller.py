"""The drive's controller the plan writes into its closed-loop sidecars: the default PID
with lead, or a spec given (checked when the toolkit can simulate its type)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...harness.controllers import CONTROLLERS, DEFAULT_LEAD, make_controller, pid_lead_spec
from ...harness.references import Reference
from .limits import PlanError, force_per_volt

#: force-equivalent gains of the plan's default controller, a PID with the registry's lead
#: filter, for a moving mass of PAPER_MASS (scaled with the model's mass): stiffer than the
#: registry's default PID so that the 0.3 mm/s runs slide steadily (the default PID's
#: speed wanders by > 25 % there on the paper's friction); margins on the paper's design
#: model: phase 38 deg, gain 5.6 dB, crossover 44 Hz
PLAN_GAINS: dict[str, float] = {"Kp": 3.0e5, "Kv": 3.5e3, "Ki": 6.0e6}
PAPER_MASS = 16.1


def default_controller(params: Mapping[str, Any], u_limit: float) -> dict[str, Any]:
    """The plan's controller when none is given: :data:`PLAN_GAINS` scaled by m / 16.1 kg,
    the registry's lead filter, anti-windup, the model's force per volt, clamp ``u_limit``."""
    scale = float(params["m"]) / PAPER_MASS
    return pid_lead_spec(
        *DEFAULT_LEAD,
        **{k: v * scale for k, v in PLAN_GAINS.items()},
        force_per_volt=force_per_volt(params),
        u_limit=u_limit,
        anti_windup=True,
    )


def check_controller(spec: Mapping[str, Any], Ts: float, notes: list[str]) -> dict[str, Any]:
    """A spec of a registry type must build; another type is kept as the drive's own
    description (a note says the closed-loop replay cannot use it)."""
    if not isinstance(spec.get("type"), str):
        raise PlanError("--controller: the spec needs a 'type' (a string)")
    if spec["type"] not in CONTROLLERS:
        notes.append(
            f"controller type {spec['type']!r} is not one the toolkit simulates "
            f"({', '.join(sorted(CONTROLLERS))}): kept in the sidecars as your "
            "description; identification does not need it, a closed-loop replay "
            "(validate) is skipped"
        )
        return dict(spec)
    ref = Reference(Ts, np.zeros(2), np.zeros(2), np.zeros(2))
    try:
        make_controller(spec, ref)
    except (ValueError, TypeError, KeyError) as e:
        raise PlanError(f"--controller: {e}") from None
    return dict(spec)
