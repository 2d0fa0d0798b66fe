"""The machine's limits the plan is sized to, and the checks that the campaign fits them.

Limits the campaign cannot fit at all raise :class:`PlanError` naming the option and the
rule.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from itertools import pairwise
from typing import Any

import numpy as np

from ...control.pid import DEFAULT_U_LIMIT
from ...model_file import ModelFile
from ...physics import CurrentLoop
from ..constant_speed import PAPER_LOADS
from ..recording import STROKE_MARGIN
from .sizes import FORCE_FRICTION_FACTOR, PRBS_AMPLITUDE

LOAD_TOL = 0.5  #: loads closer than this [N] are the same load
HOLD_SHARE = 0.8  #: a load, with static friction, may need this share of u_limit
MIN_STROKE_ROOM = 20e-3  #: travel needed inside the margins [m]
MIN_V_MAX = 1e-3  #: the large pre-rolling sinusoid moves at up to 0.79 mm/s
#: default machine limits beside the stroke (the paper's drive)
DEFAULT_V_MAX, DEFAULT_A_MAX = 0.25, 5.0


class PlanError(ValueError):
    """Limits the campaign cannot fit: the message names the option and the rule."""


@dataclass(frozen=True)
class Limits:
    """The machine's limits, SI: stroke [m], v_max [m/s], a_max [m/s^2], u_limit [V], and
    the loads [N] to hang for the maps (0 is always added)."""

    stroke: tuple[float, float]
    v_max: float = DEFAULT_V_MAX
    a_max: float = DEFAULT_A_MAX
    u_limit: float = DEFAULT_U_LIMIT
    loads: tuple[float, ...] = tuple(P for P in PAPER_LOADS if P != 0)


def default_limits(
    model: ModelFile,
    stroke: Sequence[float] | None = None,
    v_max: float | None = None,
    a_max: float | None = None,
    u_limit: float | None = None,
    loads: Sequence[float] | None = None,
) -> Limits:
    """Limits given, else the model's stroke and the paper's drive (:data:`DEFAULT_V_MAX`,
    :data:`DEFAULT_A_MAX`, ±10 V, the paper's loads 54.9 and 272.7 N)."""
    p = model.parameters
    d = Limits(stroke=(float(p.get("stroke.x_min", 0.0)), float(p.get("stroke.x_max", 0.3))))
    return Limits(
        stroke=d.stroke if stroke is None else (float(stroke[0]), float(stroke[1])),
        v_max=d.v_max if v_max is None else float(v_max),
        a_max=d.a_max if a_max is None else float(a_max),
        u_limit=d.u_limit if u_limit is None else float(u_limit),
        loads=d.loads if loads is None else tuple(float(P) for P in loads),
    )


def _finite(value: float, option: str, rule: str, ok: bool) -> None:
    if not (np.isfinite(value) and ok):
        raise PlanError(f"{option}: {value:g} is out of range: must be {rule}")


def force_per_volt(params: Mapping[str, Any]) -> float:
    """K_f0 G(1) [N/V]: the force one volt of amplifier reference makes at DC."""
    return float(params["ripple.c[0]"]) * CurrentLoop.from_parameters(params).G1


def check_limits(limits: Limits, params: Mapping[str, Any]) -> None:
    """PlanError naming the option when the campaign cannot fit ``limits`` at all."""
    x0, x1 = limits.stroke
    _finite(x0, "--stroke", "finite [m]", True)
    _finite(x1, "--stroke", f"X1 > X0 = {x0:g} m", x1 > x0)
    room = x1 - x0 - 2 * STROKE_MARGIN
    if room < MIN_STROKE_ROOM:
        raise PlanError(
            f"--stroke: {x0:g} .. {x1:g} m leaves {room * 1e3:.1f} mm inside the "
            f"{STROKE_MARGIN * 1e3:g} mm margins; the campaign needs at least "
            f"{MIN_STROKE_ROOM * 1e3:g} mm (stroke >= "
            f"{(MIN_STROKE_ROOM + 2 * STROKE_MARGIN) * 1e3:g} mm)"
        )
    _finite(
        limits.v_max,
        "--v-max",
        f">= {MIN_V_MAX:g} m/s (the large pre-rolling sinusoid moves at up to 0.79 mm/s)",
        limits.v_max >= MIN_V_MAX,
    )
    _finite(limits.a_max, "--a-max", "> 0 [m/s^2]", limits.a_max > 0)
    _finite(
        limits.u_limit,
        "--u-limit",
        f"> {PRBS_AMPLITUDE:g} V (the PRBS level)",
        limits.u_limit > PRBS_AMPLITUDE,
    )
    fpv = force_per_volt(params)
    F_s = float(params["friction.F_s"])
    budget = HOLD_SHARE * limits.u_limit
    for P in limits.loads:
        _finite(P, "--loads", "finite [N]", True)
        need = (abs(P) + F_s) / fpv
        if need > budget:
            raise PlanError(
                f"--loads: {P:g} N with static friction F_s = {F_s:g} N needs "
                f"{need:.2f} V at {fpv:.1f} N/V, more than {HOLD_SHARE:.0%} of "
                f"--u-limit {limits.u_limit:g} V; hang a lighter load or raise "
                "--u-limit"
            )
    P_all = sorted([0.0, *limits.loads])
    for a, b in pairwise(P_all):
        if b - a <= LOAD_TOL:
            raise PlanError(
                f"--loads: {a:g} and {b:g} N are closer than {LOAD_TOL:g} N (the "
                "same load to identify; 0 N is always planned)"
            )
    F_need = FORCE_FRICTION_FACTOR * F_s
    m = float(params["m"])
    if limits.u_limit * fpv < F_need:
        raise PlanError(
            f"--u-limit: {limits.u_limit:g} V makes {limits.u_limit * fpv:.1f} N; "
            f"the open-loop mass run needs {FORCE_FRICTION_FACTOR:g} F_s = "
            f"{F_need:.1f} N (u_limit >= {F_need / fpv:.2f} V)"
        )
    if limits.a_max * m < F_need:
        raise PlanError(
            f"--a-max: {limits.a_max:g} m/s^2 on m = {m:g} kg allows "
            f"{limits.a_max * m:.1f} N; the open-loop mass run needs "
            f"{FORCE_FRICTION_FACTOR:g} F_s = {F_need:.1f} N "
            f"(a_max >= {F_need / m:.2f} m/s^2)"
        )
