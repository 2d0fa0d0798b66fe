"""The plan's runs, one method per experiment of the campaign, sized to the limits."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ...effects import Experiment
from ...harness.references import Reference, point_to_point, prbs, sinusoid
from ..constant_speed import STRIBECK_SPEEDS
from ..force_open_loop import square_wave_input
from ..prerolling_excitation import AMPLITUDES as PREROLLING_AMPLITUDES
from ..recording import STROKE_MARGIN
from ..variable_speed import speed_profile
from .limits import PlanError, force_per_volt
from .runs import KIND_OF_GROUP, Plan, PlannedRun, closed_loop_columns, run_sidecar
from .sizes import (
    DWELL,
    FORCE_DURATION,
    FORCE_FRICTION_FACTOR,
    FORCE_MARGIN,
    FORCE_PERIOD,
    MAP_SPAN,
    MAP_SPEED,
    MASS_TRAVEL,
    MIN_CRUISE,
    MIN_STRIBECK_SPEEDS,
    PITCH,
    PRBS_AMPLITUDE,
    PRBS_ORDER,
    PRBS_PERIODS,
    PRBS_SETTLE,
    PREROLLING_PERIOD,
    PREROLLING_PERIODS,
    PREROLLING_SPARE,
    RAMP_ACCEL,
    SPEED_TOL,
    STRIBECK_CRUISE,
    STRIBECK_MAX_LENGTH,
    VAR_MIN_TOP,
    VAR_PERIOD,
    VAR_SPEED,
)


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
        side = run_sidecar(
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
            closed_loop_columns(ref, u_add),
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
                closed_loop_columns(ref),
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
            closed_loop_columns(ref),
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
                closed_loop_columns(ref),
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
