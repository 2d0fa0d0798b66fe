"""Test harness: drive the FMU through model exchange (fmpy's CVode) with a Python law.

The FMU tests need motions the open-loop helpers cannot give: a stage held at constant
speed, a position moved slowly through pre-rolling, a force ramp stopped at break-away.  A
*law* computes the inputs (u, F_ext) at every sample t_k = t0 + k dt from the outputs at
t_k; the FMU integrates [t_k, t_{k+1}] with fmpy's CVodeSolver and the FMI 2.0 event
handling of :class:`feeddrive.harness.simulate.Stepper` (state events located by CVode's root
finder, an event update at every sample).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from feeddrive.fmu import Plant
from feeddrive.harness.simulate import Stepper as _Stepper

#: Parameters that strip the plant down to mass + friction driven by F_ext (u = 0):
#: no cogging, no ripple, no current-loop samples (so a sample may be longer than Ts).
FRICTION_ONLY: dict[str, bool] = {
    "effects.cogging_periodic": False,
    "effects.cogging_aperiodic": False,
    "effects.ripple_periodic": False,
    "effects.ripple_aperiodic": False,
    "effects.current_dynamics": False,
}

#: law(k, t_k, outputs at t_k) -> (u, F_ext) held over [t_k, t_{k+1}]
Law = Callable[[int, float, Mapping[str, float]], tuple[float, float]]

REAL_OUT = ("x", "v", "a", "i", "F_motor", "F_cogging", "F_friction", "K_f")


@dataclass
class Run:
    """Signals at t_k (k = 0..n) and the event counts of one run."""

    sig: dict[str, np.ndarray]
    state_events: int  # CVode roots reported to the ME loop
    time_events: int  # sample instants handled in event mode
    stats: dict[str, int] = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.sig[name]


def me_plant(
    parameters: Mapping[str, float | int | bool] | None = None, tolerance: float = 1e-8
) -> Plant:
    """A model-exchange instance of the FMU (CVode) with ``parameters`` over the defaults."""
    return Plant(dict(parameters or {}), interface="me", tolerance=tolerance)


def run_law(
    plant: Plant,
    dt: float,
    n: int,
    law: Law | None,
    start: Mapping[str, float] | None = None,
    integers: Sequence[str] = ("n_stuck",),
    stop: Callable[[int, Mapping[str, float]], bool] | None = None,
) -> Run:
    """Run ``n`` samples of length ``dt`` from the start values ``start`` (u, F_ext, x, v, ...).

    At k = 0 the inputs are the start values; at k >= 1 ``law`` sets them (None: held).
    Records u, F_ext, the Real outputs and ``integers`` at every t_k, after the inputs of
    t_k were set and before the event update of t_k.  ``stop(k, outputs)`` ends the run
    early when it returns True (the signals then end at that sample).
    """
    sv = {"u": 0.0, "F_ext": 0.0}
    sv.update(start or {})
    plant.start(sv, t0=0.0)
    out = plant.raw(list(REAL_OUT))
    inp = plant.raw(["u", "F_ext"])
    stepper = _Stepper(plant, dt, 0.0)
    names = ["time", "u", "F_ext", *REAL_OUT, *integers]
    rows = np.empty((n + 1, len(names)))
    u, F = float(sv["u"]), float(sv["F_ext"])
    last = n
    for k in range(n + 1):
        t = k * dt
        y = dict(zip(REAL_OUT, out.get(), strict=True))
        if k > 0 and law is not None:
            u, F = law(k, t, y)
            inp.set((u, F))
        ints = list(plant.get(integers).values()) if integers else []
        rows[k] = [t, u, F, *[y[s] for s in REAL_OUT], *ints]
        if k == n or (stop is not None and stop(k, y | dict(zip(integers, ints, strict=True)))):
            last = k
            break
        stepper.step(k)
    sig = {s: rows[: last + 1, j].copy() for j, s in enumerate(names)}
    stats = plant.get(
        ["stats.n_stick", "stats.n_slip", "stats.n_state_events", "stats.n_time_events"]
    )
    return Run(
        sig, stepper.n_state_events, stepper.n_time_events, {k: int(v) for k, v in stats.items()}
    )


class VelocityLoop:
    """Hold the speed at ``v_ref(t)`` with F_ext: friction feedforward from the FMU's own
    F_friction output plus PI on the speed error (poles at ``bandwidth`` Hz, critically
    damped).  The plant must be friction-only (u = 0, no cogging): then at constant speed
    F_ext = -(force of friction acting on the stage)."""

    def __init__(
        self, v_ref: Callable[[float], float], m: float, dt: float, bandwidth: float = 20.0
    ) -> None:
        w = 2.0 * np.pi * bandwidth
        self.v_ref, self.dt = v_ref, dt
        self.kp, self.ki = m * w, m * w * w / 4.0
        self.integral = 0.0

    def __call__(self, k: int, t: float, y: Mapping[str, float]) -> tuple[float, float]:
        e = self.v_ref(t) - y["v"]
        self.integral += e * self.dt
        return 0.0, -(y["F_friction"] + self.kp * e + self.ki * self.integral)


def run_at_speed(
    parameters: Mapping[str, float | int | bool],
    v_ref: float,
    m: float,
    dt: float = 2e-3,
    n: int = 300,
    ramp: float = 0.02,
) -> Run:
    """Model exchange at tolerance 1e-8 from x = 0, speed ramped to ``v_ref`` in ``ramp``
    seconds and held by a :class:`VelocityLoop` (friction-only parameters)."""
    plant = me_plant(parameters)
    try:
        return run_law(
            plant, dt, n, VelocityLoop(lambda t: v_ref * min(t / ramp, 1.0), m, dt), {"x": 0.0}
        )
    finally:
        plant.close()


class PositionLoop:
    """Follow ``x_ref(t)`` (with ``v_ref``, ``a_ref``) with F_ext: friction and cogging
    feedforward from the FMU's outputs, motor force included, plus PD with poles at
    ``bandwidth`` Hz (critically damped)."""

    def __init__(
        self, ref: Callable[[float], tuple[float, float, float]], m: float, bandwidth: float = 30.0
    ) -> None:
        w = 2.0 * np.pi * bandwidth
        self.ref, self.m = ref, m
        self.kp, self.kd = w * w, 2.0 * w

    def __call__(self, k: int, t: float, y: Mapping[str, float]) -> tuple[float, float]:
        x_r, v_r, a_r = self.ref(t)
        drive = (
            y["F_friction"]
            + y["F_cogging"]
            - y["F_motor"]
            + self.m * (a_r + self.kd * (v_r - y["v"]) + self.kp * (x_r - y["x"]))
        )
        return 0.0, -drive


def triangle(
    points: Sequence[float], speed: float, t_hold: float = 0.0
) -> tuple[Callable[[float], tuple[float, float, float]], np.ndarray]:
    """Position reference through ``points`` [m] at constant ``speed`` [m/s] (a hold of
    ``t_hold`` s first).  Returns ref(t) -> (x, v, a) and the times the points are reached."""
    pts = np.asarray(points, dtype=float)
    seg_t = np.abs(np.diff(pts)) / speed
    knots = t_hold + np.concatenate([[0.0], np.cumsum(seg_t)])
    x_knots = pts

    def ref(t: float) -> tuple[float, float, float]:
        if t <= knots[0]:
            return float(x_knots[0]), 0.0, 0.0
        if t >= knots[-1]:
            return float(x_knots[-1]), 0.0, 0.0
        j = int(np.searchsorted(knots, t, side="right") - 1)
        direction = np.sign(x_knots[j + 1] - x_knots[j])
        return float(x_knots[j] + direction * speed * (t - knots[j])), float(direction * speed), 0.0

    return ref, knots


def maxwell_slip(
    x: np.ndarray, k: Sequence[float], levels: Sequence[float], F0: Sequence[float] | None = None
) -> np.ndarray:
    """Friction of the ideal Maxwell-slip model (MODEL.md, Eq. 15) along the path ``x``.

    Element i is a spring k_i whose force is clipped at +-levels[i] (a block that slides
    at that force); the total force at every point of ``x`` is returned.  Independent of
    the FMU: the expected pre-rolling curve of the tests.
    """
    k = np.asarray(k, dtype=float)
    L = np.asarray(levels, dtype=float)
    F = np.zeros_like(k) if F0 is None else np.asarray(F0, dtype=float).copy()
    out = np.empty(len(x))
    out[0] = F.sum()
    for j in range(1, len(x)):
        F = np.clip(F + k * (x[j] - x[j - 1]), -L, L)
        out[j] = F.sum()
    return out
