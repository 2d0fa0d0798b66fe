"""The identification campaign as a plan to run on a real drive, scaled to its limits.

:func:`make_plan` turns the campaign of :mod:`.campaign` (the run kinds ``identify`` needs:
PRBS, constant speed with and without load, open-loop force, variable speed, pre-rolling)
into references a drive can play, sized to the machine's :class:`Limits` (stroke, speed,
acceleration, amplifier range, loads to hang).  Each :class:`PlannedRun` holds its reference
columns (``time, x_ref`` closed loop, plus ``u_add`` for the PRBS; ``time, u`` open loop),
the sidecar to keep with its recording (:mod:`feeddrive.harness.sidecar` form), the load to
hang, and what it identifies.

Limits the campaign cannot fit at all raise :class:`PlanError` naming the option and the
rule.  Limits that only leave some parameters unidentifiable (a stroke shorter than the maps
need, too few Stribeck speeds below ``--v-max``) give a plan whose ``not_identified`` says
which parameters and why; ``identify`` then keeps the model's values for them.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from itertools import pairwise
from typing import Any, cast

import numpy as np

from ..control.pid import DEFAULT_U_LIMIT
from ..effects import Experiment, experiments, resolve
from ..harness.controllers import CONTROLLERS, DEFAULT_LEAD, make_controller, pid_lead_spec
from ..harness.references import Reference, point_to_point, prbs, sinusoid
from ..harness.sidecar import SCHEMA
from ..model_file import ModelFile
from ..paper import MAGNET_PITCH_MM, MM
from ..physics import CurrentLoop
from .constant_speed import PAPER_LOADS, STRIBECK_SPEEDS
from .force_open_loop import square_wave_input
from .prerolling_excitation import AMPLITUDES as PREROLLING_AMPLITUDES
from .recording import HOLD, STROKE_MARGIN
from .variable_speed import speed_profile

PITCH = MAGNET_PITCH_MM * MM  #: magnet pitch [m]
#: shortest stroke [m] the loaded constant-speed runs must share for the maps (Eqs. 6-7):
#: two magnet pitches (``identify``'s ``min_map_span``)
MAP_SPAN = 2 * PITCH
#: speed of the constant-speed runs for the maps [m/s] (Eq. 3 cancels friction symmetric in
#: v, so the speed is free: 10 mm/s crosses 0.3 m in 30 s)
MAP_SPEED = 10e-3
#: the Stribeck runs' candidate speeds are the campaign's (constant_speed.STRIBECK_SPEEDS)
MIN_STRIBECK_SPEEDS = 6  #: Eq. 12's fit needs >= 6 speeds (both directions each)
STRIBECK_CRUISE = 60.0  #: cruise time aimed at [s], ...
STRIBECK_MAX_LENGTH = 0.24  #: ... within one pitch .. this length [m]
MIN_CRUISE = (1.0, 3e-3)  #: a speed needs a cruise of >= 1 s and >= 3 mm to count
RAMP_ACCEL = 0.5  #: acceleration of the constant-speed ramps [m/s^2] (capped by a_max)
DWELL = 0.5  #: rest before and after each constant-speed move [s]
SPEED_TOL = 0.1  #: relative distance within which two speeds are the same
LOAD_TOL = 0.5  #: loads closer than this [N] are the same load
HOLD_SHARE = 0.8  #: a load, with static friction, may need this share of u_limit
PRBS_AMPLITUDE = 0.3  #: PRBS level +- [V] added to the controller's output
PRBS_ORDER, PRBS_PERIODS, PRBS_SETTLE = 11, 4, 0.1
FORCE_MARGIN = 2e-3  #: the open-loop run stops this close to a stroke end [m]
FORCE_PERIOD = 0.2  #: square-wave period aimed at [s]
#: travel between the open-loop run's reversals [m]: ``identify``'s mass step leaves out
#: 1 mm after each reversal and every sample slower than 10 mm/s
MASS_TRAVEL = 4e-3
FORCE_DURATION = 2.0  #: length of the square wave [s]
FORCE_FRICTION_FACTOR = 2.0  #: the open-loop force must reach this multiple of F_s
VAR_SPEED = (1e-3, 20e-3)  #: speed range of the variable-speed run [m/s], period below
VAR_PERIOD = 0.5
VAR_MIN_TOP = 5e-3  #: its top speed must reach this [m/s] (S(v) must change)
PREROLLING_PERIOD, PREROLLING_PERIODS = 4.0, 3.0
PREROLLING_SPARE = 10e-6  #: the small amplitude keeps this from Delta_N-1 and Delta_N [m]
MIN_STROKE_ROOM = 20e-3  #: travel needed inside the margins [m]
MIN_V_MAX = 1e-3  #: the large pre-rolling sinusoid moves at up to 0.79 mm/s
#: force-equivalent gains of the plan's default controller, a PID with the registry's lead
#: filter, for a moving mass of PAPER_MASS (scaled with the model's mass): stiffer than the
#: registry's default PID so that the 0.3 mm/s runs slide steadily (the default PID's
#: speed wanders by > 25 % there on the paper's friction); margins on the paper's design
#: model: phase 38 deg, gain 5.6 dB, crossover 44 Hz
PLAN_GAINS: dict[str, float] = {"Kp": 3.0e5, "Kv": 3.5e3, "Ki": 6.0e6}
PAPER_MASS = 16.1
#: default machine limits beside the stroke (the paper's drive)
DEFAULT_V_MAX, DEFAULT_A_MAX = 0.25, 5.0

#: what each run group identifies (``identify``'s steps), for the plan page: the experiments
#: the effects declare (:func:`feeddrive.effects.experiments`), in campaign order
IDENTIFIES: dict[str, str] = {x.page_group: x.identifies for x in experiments()}
#: the same, in a few words (the page's table of runs)
IDENTIFIES_SHORT: dict[str, str] = {x.page_group: x.short for x in experiments()}
#: the sidecar kind of each run group
KIND_OF_GROUP: dict[str, str] = {x.page_group: x.kind for x in experiments()}


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


@dataclass
class PlannedRun:
    """One run of the plan: its reference columns, sidecar and purpose."""

    name: str  #: file stem (order number and run)
    group: str  #: key of :data:`IDENTIFIES`
    kind: str  #: the sidecar's ``kind``
    columns: dict[str, np.ndarray]  #: the reference CSV: time and x_ref [, u_add] or u
    sidecar: dict[str, Any]
    load: float  #: load to hang [N]
    moves: str  #: what the stage does, for the page
    why: str  #: what it identifies and why it is shaped so

    @property
    def closed_loop(self) -> bool:
        return "x_ref" in self.columns

    @property
    def duration(self) -> float:
        """Length of the reference [s]."""
        t = self.columns["time"]
        return float(t[-1] - t[0])


@dataclass
class Plan:
    """The runs in order, the limits and what they leave unidentified."""

    model_name: str
    limits: Limits
    Ts: float
    controller: dict[str, Any] | None  #: None: the drive's controller is not described
    runs: list[PlannedRun] = field(default_factory=list)
    #: parameters -> why the plan cannot identify them under these limits
    not_identified: dict[str, str] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    @property
    def duration(self) -> float:
        """Sum of the references' lengths [s] (holds and load changes not counted)."""
        return sum(r.duration for r in self.runs)


# ---------------------------------------------------------------- checks
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


def _check_controller(spec: Mapping[str, Any], Ts: float, notes: list[str]) -> dict[str, Any]:
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


# ---------------------------------------------------------------- the runs
def _sidecar(
    kind: str,
    Ts: float,
    controller: Mapping[str, Any] | None,
    load: float,
    closed_loop: bool,
    /,
    **extra: Any,
) -> dict[str, Any]:
    meta: dict[str, Any] = {
        "schema": SCHEMA,
        "experiment": kind,
        "Ts": Ts,
        "controller": None if controller is None else dict(controller),
        "F_load": float(load),
        "kind": kind,
    }
    if closed_loop:
        meta["hold_before_record"] = HOLD
    meta.update(extra)
    return meta


def _closed(ref: Reference, u_add: np.ndarray | None = None) -> dict[str, np.ndarray]:
    cols = {"time": ref.time, "x_ref": ref.x}
    if u_add is not None:
        cols["u_add"] = u_add
    return cols


class PlanBuilder:
    """Collects the runs of one plan (the shared quantities in one place): one method per
    experiment of the campaign, ``(self, experiment)``, named by the experiment
    (:attr:`feeddrive.effects.Experiment.plan`)."""

    def __init__(self, plan: Plan, params: Mapping[str, Any]):
        self.plan, self.p = plan, params
        self.Ts = plan.Ts
        lim = plan.limits
        self.lo, self.hi = lim.stroke[0] + STROKE_MARGIN, lim.stroke[1] - STROKE_MARGIN
        self.mid = 0.5 * (self.lo + self.hi)
        self.accel = min(RAMP_ACCEL, lim.a_max)
        #: speed of the map runs [m/s] once planned (None: none; also a Stribeck point)
        self.map_speed: float | None = None

    def add(
        self,
        group: str,
        stem: str,
        columns: dict[str, np.ndarray],
        load: float,
        moves: str,
        why: str,
        closed_loop: bool = True,
        **extra: Any,
    ) -> None:
        name = f"{len(self.plan.runs) + 1:02d}_{stem}"
        kind = KIND_OF_GROUP[group]
        side = _sidecar(
            kind,
            self.Ts,
            self.plan.controller if closed_loop else None,
            load,
            closed_loop,
            name=name,
            group=group,
            **extra,
        )
        self.plan.runs.append(PlannedRun(name, group, kind, columns, side, float(load), moves, why))

    def prbs(self, exp: Experiment) -> None:
        seq = prbs(PRBS_ORDER, amplitude=PRBS_AMPLITUDE, periods=PRBS_PERIODS)
        k0 = int(round(PRBS_SETTLE / self.Ts))
        u_add = np.concatenate([np.zeros(k0), seq, [0.0]])
        n = len(u_add)
        ref = Reference(self.Ts, np.full(n, self.mid), np.zeros(n), np.zeros(n))
        self.add(
            exp.page_group,
            "prbs",
            _closed(ref, u_add),
            0.0,
            f"holds x = {self.mid:.4f} m; u_add (+-{PRBS_AMPLITUDE:g} V PRBS) is added "
            "to the controller's output",
            f"a maximum-length sequence of order {PRBS_ORDER} "
            "excites the current loop up to the Nyquist frequency while the position "
            "loop holds the stage",
            position=self.mid,
            order=PRBS_ORDER,
            amplitude=PRBS_AMPLITUDE,
            periods=PRBS_PERIODS,
            prbs_start=k0,
            prbs_period=2**PRBS_ORDER - 1,
            note="record u as the total voltage: the controller's output plus u_add",
        )

    def constant_speed(
        self, group: str, v: float, P: float, lo: float, hi: float, why: str
    ) -> None:
        for d in (1, -1):
            x0, x1 = (lo, hi) if d > 0 else (hi, lo)
            ref = point_to_point(x0, x1, v, self.accel, dwell=DWELL, Ts=self.Ts)
            stem = f"cv_{'p' if d > 0 else 'm'}{v * 1e3:g}mm_s_P{P:g}"
            self.add(
                group,
                stem,
                _closed(ref),
                P,
                f"{x0:.4f} -> {x1:.4f} m at {v * 1e3:g} mm/s",
                why,
                speed=v,
                direction=d,
                P=P,
                segment=[x0, x1],
                accel=self.accel,
                dwell=DWELL,
            )

    def map_runs(self, exp: Experiment) -> None:
        """The loaded and unloaded runs over the whole usable stroke; their speed is
        :attr:`map_speed`."""
        lim = self.plan.limits
        v = min(MAP_SPEED, lim.v_max)
        span = self.hi - self.lo - v**2 / self.accel
        params = "ripple.*, cogging.* (K_f(x), F_cg(x))"
        if span < MAP_SPAN:
            self.plan.not_identified[params] = (
                f"the stroke leaves {span * 1e3:.1f} mm at constant speed; Eqs. 6-7 (a cubic and "
                f"three harmonics of the {PITCH * 1e3:g} mm magnet pitch) need "
                f"{MAP_SPAN * 1e3:g} mm (stroke >= {(MAP_SPAN + 2 * STROKE_MARGIN) * 1e3:g} mm "
                "plus the ramps)"
            )
            return
        if not lim.loads:
            self.plan.not_identified[params] = (
                "no load besides 0 N (--loads): Eqs. 4-5 separate K_f and F_cg with two loads"
            )
            return
        for P in (0.0, *lim.loads):
            self.constant_speed(
                exp.page_group,
                v,
                P,
                self.lo,
                self.hi,
                f"the mean current of the two directions "
                f"at load {P:g} N is (F_cg(x) + P) / K_f(x) (Eq. 3)"
                + ("; the unloaded pair is also a Stribeck point" if P == 0 else ""),
            )
        self.map_speed = v

    def stribeck_runs(self, exp: Experiment) -> None:
        lim = self.plan.limits
        kept: list[float] = [] if self.map_speed is None else [self.map_speed]
        dropped: list[str] = []
        planned: list[tuple[float, float, float]] = []
        for v in STRIBECK_SPEEDS:
            if any(abs(v - q) <= SPEED_TOL * q for q in kept):
                continue
            if v > lim.v_max:
                dropped.append(f"{v * 1e3:g} mm/s (above --v-max)")
                continue
            ramp = v**2 / self.accel
            room = self.hi - self.lo - ramp
            L = min(float(np.clip(v * STRIBECK_CRUISE, PITCH, STRIBECK_MAX_LENGTH)), room)
            if L < max(MIN_CRUISE[0] * v, MIN_CRUISE[1]):
                dropped.append(
                    f"{v * 1e3:g} mm/s (cruise of {max(L, 0) * 1e3:.1f} mm: the "
                    "stroke is too short)"
                )
                continue
            half = 0.5 * (L + ramp)
            c = min(max(self.mid, self.lo + half), self.hi - half)
            planned.append((v, c - half, c + half))
            kept.append(v)
        if len(kept) < MIN_STRIBECK_SPEEDS:
            self.plan.not_identified["friction.F_s, F_c, V_s, delta, sigma2"] = (
                f"{len(kept)} speeds fit the limits ({', '.join(f'{v * 1e3:g}' for v in sorted(kept))}"
                f" mm/s); Eq. 12 needs {MIN_STRIBECK_SPEEDS}"
                + (f"; left out: {', '.join(dropped)}" if dropped else "")
            )
            return
        if dropped:
            self.plan.notes.append("Stribeck speeds left out: " + ", ".join(dropped))
        top = max(kept)
        if top < 10 * float(self.p["friction.V_s"]):
            self.plan.notes.append(
                f"the fastest Stribeck speed, {top * 1e3:g} mm/s, is below 10 V_s "
                f"({10 * float(self.p['friction.V_s']) * 1e3:.3g} mm/s): F_c and sigma2 are "
                "weakly separated"
            )
        for v, a, b in planned:
            self.constant_speed(
                exp.page_group,
                v,
                0.0,
                a,
                b,
                f"half the current difference of "
                f"the two directions is the friction at {v * 1e3:g} mm/s "
                "(Eq. 13, averaged over the segment)",
            )

    def force_open_loop(self, exp: Experiment) -> None:
        lim, p = self.plan.limits, self.p
        m, F_s, F_c = float(p["m"]), float(p["friction.F_s"]), float(p["friction.F_c"])
        fpv = force_per_volt(p)
        A = min(max(1.0, FORCE_FRICTION_FACTOR * F_s / fpv), lim.u_limit, lim.a_max * m / fpv)
        a_net = (A * fpv - F_c) / m  # while sliding
        room = 0.5 * (self.hi - self.lo) - FORCE_MARGIN
        T = min(FORCE_PERIOD, 4 * lim.v_max / a_net)
        if a_net * T**2 / 16 < MASS_TRAVEL:  # too little travel between reversals:
            a_net = lim.v_max**2 / MASS_TRAVEL  # a lower force, longer, up to v_max
            a_low = (FORCE_FRICTION_FACTOR * F_s - F_c) / m
            if a_net < a_low:
                raise PlanError(
                    f"--v-max: {lim.v_max:g} m/s; the open-loop mass run needs "
                    f"{FORCE_FRICTION_FACTOR:g} F_s = {FORCE_FRICTION_FACTOR * F_s:.1f} N and "
                    f"{MASS_TRAVEL * 1e3:g} mm of travel between reversals: v_max >= "
                    f"{np.sqrt(MASS_TRAVEL * a_low):.3g} m/s"
                )
            T = 4 * lim.v_max / a_net
            A = (a_net * m + F_c) / fpv
        T = min(T, float(np.sqrt(16 * room / a_net)))
        F = A * fpv
        T = self.Ts * 2 * max(2, int(round(T / (2 * self.Ts))))
        n_periods = max(2, int(round(FORCE_DURATION / T)))
        u = square_wave_input(self.Ts, A, T, n_periods, 0.0, 0.1)
        cols = {"time": np.arange(len(u)) * self.Ts, "u": u}
        v_peak = a_net * T / 4
        self.add(
            exp.page_group,
            "force_open_loop",
            cols,
            0.0,
            f"open loop from rest at x = {self.mid:.4f} m: +-{A:.3g} V square wave, period "
            f"{T * 1e3:.0f} ms (~{v_peak * 1e3:.0f} mm/s, ~{a_net * T**2 / 16 * 1e3:.1f} mm "
            f"of travel); stop where the stage comes within {FORCE_MARGIN * 1e3:g} mm of a "
            "stroke end",
            f"without a controller the force steps of "
            f"{F:.0f} N (> {FORCE_FRICTION_FACTOR:g} F_s) accelerate the stage; the "
            "identified maps and friction are subtracted",
            closed_loop=False,
            position=self.mid,
            amplitude=A,
            period=T,
            n_periods=n_periods,
            bias=0.0,
            rest=0.1,
            stop_outside=[lim.stroke[0] + FORCE_MARGIN, lim.stroke[1] - FORCE_MARGIN],
        )

    def variable_speed(self, exp: Experiment) -> None:
        lim = self.plan.limits
        v_min, v_top = VAR_SPEED[0], min(VAR_SPEED[1], lim.v_max)
        if v_top < VAR_MIN_TOP:
            self.plan.not_identified["friction.C"] = (
                f"the variable-speed run needs speeds up to {VAR_MIN_TOP * 1e3:g} mm/s "
                f"(--v-max {lim.v_max * 1e3:g} mm/s): S(v) must change along the run"
            )
            return
        period = max(VAR_PERIOD, np.pi * (v_top - v_min) / lim.a_max)
        x0 = self.lo + STROKE_MARGIN
        v_mean = 0.5 * (v_min + v_top)
        room = self.hi - x0 - 0.4 * v_top
        n_per = int(room / v_mean / period)
        if n_per < 1:
            self.plan.not_identified["friction.C"] = (
                f"one period of the speed variation ({period:g} s at {v_mean * 1e3:.3g} mm/s) "
                f"needs {period * v_mean * 1e3:.1f} mm; the stroke leaves {room * 1e3:.1f} mm"
            )
            return
        duration = period * n_per
        v, k_begin, k_end = speed_profile(self.Ts, v_min, v_top, period, duration)
        x = x0 + np.concatenate([[0.0], np.cumsum((v[1:] + v[:-1]) / 2 * self.Ts)])
        ref = Reference(self.Ts, x, v, np.gradient(v, self.Ts))
        self.add(
            exp.page_group,
            "variable_speed",
            _closed(ref),
            0.0,
            f"{x[0]:.4f} -> {x[-1]:.4f} m, speed {v_min * 1e3:g} .. {v_top * 1e3:g} mm/s "
            f"varying with period {period:g} s, never reversing",
            "every GMS element slips while S(v) changes, so the frictional lag shows C",
            direction=1,
            v_min=v_min,
            v_max=v_top,
            period=period,
            duration=duration,
            x_start=x0,
            variable_phase=[k_begin * self.Ts, k_end * self.Ts],
        )

    def prerolling_amplitudes(self) -> tuple[float, float]:
        """The small amplitude between the nominal model's Delta_N-1 and Delta_N (the
        campaign's 80 um when it lies there with 10 um to spare), the large one past 2 Delta_N
        (the campaign's 0.5 mm, or 1.2 Delta_N when that is larger)."""
        p = self.p
        N = int(p.get("friction.N", 0))
        small, large = min(PREROLLING_AMPLITUDES), max(PREROLLING_AMPLITUDES)
        if N < 2:
            return small, large
        D = [
            float(p[f"friction.nu[{j}]"]) * float(p["friction.F_s"]) / float(p[f"friction.k[{j}]"])
            for j in (N - 1, N)
        ]
        if not D[0] + PREROLLING_SPARE < small < D[1] - PREROLLING_SPARE:
            small = 0.5 * (D[0] + D[1])
            self.plan.notes.append(
                f"pre-rolling: the small amplitude is {small * 1e6:.0f} um, midway between the "
                f"model's Delta_{N - 1} = {D[0] * 1e6:.0f} um and Delta_{N} = {D[1] * 1e6:.0f} um"
            )
        return small, max(large, 1.2 * D[1])

    def prerolling(self, exp: Experiment) -> None:
        for A in self.prerolling_amplitudes():
            ref = sinusoid(
                A, PREROLLING_PERIOD, self.mid, PREROLLING_PERIODS * PREROLLING_PERIOD, Ts=self.Ts
            )
            small = A < max(PREROLLING_AMPLITUDES) - 1e-12
            self.add(
                exp.page_group,
                f"{exp.stem}_A{A * 1e6:.0f}um",
                _closed(ref),
                0.0,
                f"x = {self.mid:.4f} - {A * 1e6:.0f} um cos(2 pi t / {PREROLLING_PERIOD:g} s)",
                "a travel that passes the slope changes of the force-position curve "
                "below gross sliding"
                if small
                else "gross sliding at every reversal gives the end of pre-rolling",
                amplitude=A,
                period=PREROLLING_PERIOD,
                n_periods=PREROLLING_PERIODS,
                centre=self.mid,
                reference="x_ref = centre - amplitude cos(2 pi t / period)",
            )


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
        spec = _check_controller(controller, Ts, notes)
    plan = Plan(model_name=model.name, limits=limits, Ts=Ts, controller=spec, notes=notes)
    b = PlanBuilder(plan, params)
    for exp in experiments():
        cast(Callable[[PlanBuilder, Experiment], None], resolve(exp.plan))(b, exp)
    return plan
