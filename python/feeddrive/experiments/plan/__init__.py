"""The identification campaign as a plan to run on a real drive, scaled to its limits.

:func:`make_plan` turns the campaign of :mod:`feeddrive.experiments.campaign` (the run kinds
``identify`` needs: PRBS, constant speed with and without load, open-loop force, variable
speed, pre-rolling) into references a drive can play, sized to the machine's :class:`Limits`
(stroke, speed, acceleration, amplifier range, loads to hang).  Each :class:`PlannedRun`
holds its reference columns (``time, x_ref`` closed loop, plus ``u_add`` for the PRBS;
``time, u`` open loop), the sidecar to keep with its recording
(:mod:`feeddrive.harness.sidecar` form), the load to hang, and what it identifies.

Limits the campaign cannot fit at all raise :class:`PlanError` naming the option and the
rule.  Limits that only leave some parameters unidentifiable (a stroke shorter than the maps
need, too few Stribeck speeds below ``--v-max``) give a plan whose ``not_identified`` says
which parameters and why; ``identify`` then keeps the model's values for them.

The modules, in the order of the work:

- :mod:`.sizes`: the numbers that size each run kind;
- :mod:`.limits`: the machine's :class:`Limits` and :func:`check_limits`;
- :mod:`.runs`: :class:`Plan`, :class:`PlannedRun` and their sidecars;
- :mod:`.builder`: :class:`PlanBuilder`, one method per experiment of the campaign;
- :mod:`.controller`: the controller written into the sidecars;
- :mod:`.make`: :func:`make_plan`;
- :mod:`.page` and :mod:`.files`: the plan's page and folder (``feeddrive plan``).
"""

from .builder import PlanBuilder
from .controller import PLAN_GAINS, default_controller
from .limits import Limits, PlanError, check_limits, default_limits, force_per_volt
from .make import make_plan
from .runs import IDENTIFIES, IDENTIFIES_SHORT, KIND_OF_GROUP, Plan, PlannedRun
from .sizes import MAP_SPAN

__all__ = [
    "IDENTIFIES",
    "IDENTIFIES_SHORT",
    "KIND_OF_GROUP",
    "MAP_SPAN",
    "PLAN_GAINS",
    "Limits",
    "Plan",
    "PlanBuilder",
    "PlanError",
    "PlannedRun",
    "check_limits",
    "default_controller",
    "default_limits",
    "force_per_volt",
    "make_plan",
]
