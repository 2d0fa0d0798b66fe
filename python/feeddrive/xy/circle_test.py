"""The ISO 230-4 circular test on the X-Y table: each case (radius, feed, feedforward) run in
the requested directions on four FMUs (two controller FMUs, two plant FMUs,
:func:`feeddrive.xy.table.simulate_axes`) and evaluated (:mod:`.circular`).

Controllers: the Sec. 4 state-space controller with ZPETC, designed on each axis's nominal
model; feedforward cases as Sec. 4: ``none`` (no feedforward), ``static`` (Tustin friction)
and ``gms`` (GMS friction), the latter two with cogging and ripple compensation, running on
the axis's nominal model.  The scale (100 nm) is read by the controller FMU
(``scale.quantum``); the evaluation uses the stages' true positions.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..control.feedforward import FeedforwardOptions, FrictionFeedforward
from ..harness.controller_fmu import controller_fmu_parameters
from ..harness.controllers import state_space_spec
from .circular import (
    Glitch,
    Trace,
    bidirectional_deviation,
    glitch_window,
    glitches,
    hysteresis,
    trace,
)
from .machine import AxisModel
from .path import DIRECTIONS, CirclePath, circle_path
from .table import AxisLoop, simulate_axes

FEEDFORWARD: dict[str, FrictionFeedforward | None] = {
    "none": None,
    "static": "static",
    "gms": "gms",
}
QUANTUM = 1e-7
MIN_PER_M_S = 60.0  #: feed: 1 m/s = 60 m/min


def controller_values(axis: AxisModel, feedforward: str, Ts: float = 5e-4) -> dict[str, Any]:
    """The controller FMU's parameters of an axis (reference from the inputs)."""
    if feedforward not in FEEDFORWARD:
        raise ValueError(f"feedforward = {feedforward!r}: allowed {', '.join(FEEDFORWARD)}")
    fr = FEEDFORWARD[feedforward]
    nominal = dict(axis.nominal)
    nominal["Ts"] = Ts
    spec = state_space_spec(
        nominal, feedforward=None if fr is None else FeedforwardOptions(friction=fr)
    )
    return controller_fmu_parameters(spec, Ts=Ts, quantum=QUANTUM)


@dataclass
class CircleRun:
    """One direction of one case: the path, the actual positions, the evaluation."""

    path: CirclePath
    x: np.ndarray
    y: np.ndarray
    trace: Trace
    glitches: list[Glitch]
    wall: float


def centre_of(axes: Sequence[AxisModel]) -> tuple[float, float]:
    """Mid-stroke of each axis [m]."""
    return tuple(
        0.5
        * (float(a.nominal.get("stroke.x_min", 0.0)) + float(a.nominal.get("stroke.x_max", 0.3)))
        for a in axes
    )  # type: ignore[return-value]


def check_fits(axes: Sequence[AxisModel], radius: float) -> None:
    """ValueError unless a circle of ``radius`` [m] about mid-stroke fits every axis's stroke."""
    if not (isinstance(radius, (int, float)) and np.isfinite(radius) and radius > 0):
        raise ValueError(f"circle: radius = {radius!r} must be a finite number > 0 [m]")
    for a in axes:
        lo, hi = (
            float(a.nominal.get("stroke.x_min", 0.0)),
            float(a.nominal.get("stroke.x_max", 0.3)),
        )
        if radius >= (hi - lo) / 2:
            raise ValueError(
                f"circle: radius {radius * 1e3:g} mm does not fit axis {a.name}'s "
                f"stroke {lo * 1e3:g}..{hi * 1e3:g} mm about its middle"
            )


def run_circle(
    axes: Sequence[AxisModel],
    radius: float,
    feed: float,
    direction: str,
    feedforward: str,
    Ts: float = 5e-4,
    tolerance: float = 1e-6,
    controllers: Sequence[Mapping[str, Any]] | None = None,
) -> CircleRun:
    """Run one circle on the table ``axes`` (X, Y) and evaluate its 360 deg."""
    check_fits(axes, radius)
    path = circle_path(radius, feed, direction, centre=centre_of(axes), Ts=Ts)
    ctrls = controllers or [controller_values(a, feedforward, Ts) for a in axes]
    loops = [
        AxisLoop(a.name, a.plant, c, ref)
        for a, c, ref in zip(axes, ctrls, (path.x, path.y), strict=True)
    ]
    res = simulate_axes(loops, Ts=Ts, tolerance=tolerance)
    x, y = res[axes[0].name]["x"], res[axes[1].name]["x"]
    sl = slice(path.eval_start, path.eval_stop)
    tr = trace(x[sl], y[sl], radius, direction)
    return CircleRun(
        path, x, y, tr, glitches(tr, glitch_window(radius, feed)), float(res[axes[0].name]["wall"])
    )


@dataclass
class CircleCase:
    """A case in every direction asked, and its figures."""

    radius: float
    feed: float
    feedforward: str
    runs: dict[str, CircleRun] = field(default_factory=dict)

    @property
    def H(self) -> float:
        """Circular hysteresis [m] (NaN unless both directions ran)."""
        if set(self.runs) != set(DIRECTIONS):
            return float("nan")
        return hysteresis(self.runs["cw"].trace, self.runs["ccw"].trace)

    @property
    def G_b(self) -> float:
        if set(self.runs) != set(DIRECTIONS):
            return float("nan")
        return bidirectional_deviation(self.runs["cw"].trace, self.runs["ccw"].trace)

    def max_glitch(self) -> float:
        """Largest |glitch height| over directions and quadrants [m]."""
        return max(abs(g.height) for r in self.runs.values() for g in r.glitches)

    def row(self) -> dict[str, Any]:
        """Table row: figures in um, feed in m/min."""
        out: dict[str, Any] = {
            "radius_mm": self.radius * 1e3,
            "feed_m_min": self.feed * MIN_PER_M_S,
            "feedforward": self.feedforward,
        }
        for d, r in self.runs.items():
            out[f"G_{d}_um"] = r.trace.G * 1e6
        out["H_um"], out["G_b_um"] = self.H * 1e6, self.G_b * 1e6
        for d, r in self.runs.items():
            out[f"F_max_{d}_um"], out[f"F_min_{d}_um"] = r.trace.F_max * 1e6, r.trace.F_min * 1e6
            for g in r.glitches:
                out[f"glitch_{d}_{g.angle_deg:.0f}_um"] = g.height * 1e6
        out["max_glitch_um"] = self.max_glitch() * 1e6
        out["wall_s"] = sum(r.wall for r in self.runs.values())
        return out


def circular_case(
    axes: Sequence[AxisModel],
    radius: float,
    feed: float,
    feedforward: str,
    directions: Sequence[str] = ("ccw", "cw"),
    Ts: float = 5e-4,
    tolerance: float = 1e-6,
    controllers: Sequence[Mapping[str, Any]] | None = None,
) -> CircleCase:
    """Both (or the given) directions of one case (``controllers``: the axes' controller
    FMU parameters, default :func:`controller_values`)."""
    ctrls = controllers or [controller_values(a, feedforward, Ts) for a in axes]
    case = CircleCase(float(radius), float(feed), feedforward)
    for d in directions:
        case.runs[d] = run_circle(axes, radius, feed, d, feedforward, Ts, tolerance, ctrls)
    return case


def circle_table(cases: Sequence[CircleCase]) -> str:
    """The printed table: G per direction, H, glitch heights (CCW / CW) per quadrant [um]."""
    head = (
        f"{'r [mm]':>6s} {'F [m/min]':>9s} {'FF':>6s} {'G ccw':>6s} {'G cw':>6s} {'H':>6s} "
        + " ".join(f"{f'glitch {q}':>13s}" for q in ("0", "90", "180", "270"))
        + f" {'wall [s]':>8s}"
    )
    lines = [
        "ISO 230-4 circular test, X-Y table (4 FMUs); G, H and quadrant glitch heights "
        "[um], glitch ccw/cw (+ outwards)",
        head,
    ]
    for c in cases:
        r = c.row()

        def fig(key: str, r: dict[str, Any] = r) -> str:
            v = r.get(key)
            return "-" if v is None or not np.isfinite(v) else f"{v:.1f}"

        gl = []
        for q in ("0", "90", "180", "270"):
            gl.append(f"{fig(f'glitch_ccw_{q}_um') + '/' + fig(f'glitch_cw_{q}_um'):>13s}")
        lines.append(
            f"{r['radius_mm']:6.0f} {r['feed_m_min']:9.2f} {c.feedforward:>6s} "
            f"{fig('G_ccw_um'):>6s} {fig('G_cw_um'):>6s} {fig('H_um'):>6s} "
            + " ".join(gl)
            + f" {r['wall_s']:8.2f}"
        )
    return "\n".join(lines)
