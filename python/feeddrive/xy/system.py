"""The X-Y table's circular test as an OSP system structure for libcosim: four FMUs (a
controller FMU and a plant FMU per axis), each controller on its internal reference
generator, the circle as two phase-shifted sinusoids.

The generator has no ramped start: the stages start at rest on the circle at 45 deg while
the reference already moves at feed, so the first revolution is the start transient (ISO
230-4 leaves it out) and the second one, again from 45 deg, is evaluated.  Components
``x_controller``, ``x_plant``, ``y_controller``, ``y_plant``; connections per axis plant
``x`` -> controller ``x_meas``, controller ``u`` -> plant ``u``; libcosim's fixed-step
(Jacobi) algorithm at Ts / ``jacobi_substeps`` (the controller's u lags x by one such step,
see :mod:`feeddrive.systems.engines`).  :func:`master_run` runs the same system on
:func:`feeddrive.xy.table.simulate_axes` (the harness's convention) for comparison.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from fmpy import read_model_description

from ..fmu import fmu_path
from ..harness.controller_fmu import controller_fmu_path, sinusoid_source
from ..harness.references import Reference
from ..systems.engines import quiet_libcosim
from ..systems.files import osp_structure
from .circle_test import centre_of, check_fits, controller_values
from .machine import AxisModel
from .path import DIRECTIONS
from .table import AxisLoop, simulate_axes

START_DEG = 45.0


@dataclass
class XYSystem:
    """A circle on the X-Y table as four components, their start values, the timing."""

    name: str
    axes: tuple[str, str]
    plants: dict[str, dict[str, Any]]
    controllers: dict[str, dict[str, Any]]
    x0: dict[str, float]
    radius: float
    Ts: float
    n: int
    period: float
    tolerance: float = 1e-6
    jacobi_substeps: int = 10

    @property
    def eval_slice(self) -> slice:
        """The second revolution's samples (from 45 deg again)."""
        k = int(round(self.period / self.Ts))
        return slice(k, 2 * k)

    def reference(self, axis: str) -> Reference:
        """The axis's reference as the internal generator makes it (sample j: t = j Ts)."""
        c = self.controllers[axis]
        t = np.arange(self.n + 1) * self.Ts
        w = 2 * np.pi / c["ref.period"]
        th = w * t + c["ref.phase"]
        A = c["ref.amplitude"]
        return Reference(
            self.Ts, c["ref.centre"] - A * np.cos(th), A * w * np.sin(th), A * w**2 * np.cos(th)
        )


def circle_system(
    axes: Sequence[AxisModel],
    radius: float,
    feed: float,
    direction: str,
    feedforward: str,
    Ts: float = 5e-4,
) -> XYSystem:
    """The circle of ``radius`` [m] at ``feed`` [m/s], two revolutions from 45 deg."""
    check_fits(axes, radius)
    if direction not in DIRECTIONS:
        raise ValueError(f"circle: direction = {direction!r}: allowed 'ccw' or 'cw'")
    s = DIRECTIONS[direction]
    period = 2 * np.pi * radius / feed
    duration = 2 * period
    th0 = np.deg2rad(START_DEG)
    # X = cx + r cos(th0 + s w t) = cx - r cos(w t + s th0 + pi); Y = cy - r cos(w t + s (th0 + pi/2))
    phases = (s * th0 + np.pi, s * (th0 + np.pi / 2))
    names = (axes[0].name, axes[1].name)
    plants, ctrls, x0 = {}, {}, {}
    for a, c, ph in zip(axes, centre_of(axes), phases, strict=True):
        values = controller_values(a, feedforward, Ts)
        values.update(sinusoid_source(radius, period, c, duration, ph))
        ctrls[a.name] = values
        plants[a.name] = dict(a.plant)
        x0[a.name] = float(c - radius * np.cos(ph))
    name = f"circle_r{radius * 1e3:g}mm_F{feed * 60:g}mmin_{direction}_{feedforward}".replace(
        ".", "p"
    )
    return XYSystem(
        name=name,
        axes=names,
        plants=plants,
        controllers=ctrls,
        x0=x0,
        radius=float(radius),
        Ts=Ts,
        n=int(round(duration / Ts)),
        period=period,
    )


def _literal(kind: str, value: Any) -> str:
    if kind == "Boolean":
        return "true" if value else "false"
    if kind == "Integer":
        return str(int(value))
    return repr(float(value))


def _typed(fmu: Path, values: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    types = {
        v.name: v.type for v in read_model_description(str(fmu), validate=False).modelVariables
    }
    bad = sorted(set(values) - set(types))
    if bad:
        raise ValueError(f"{fmu}: no variable(s) {bad}")
    return [(k, types[k], _literal(types[k], v)) for k, v in values.items()]


def components(system: XYSystem) -> dict[str, tuple[Path, dict[str, Any]]]:
    """name -> (FMU, start values) of the four components."""
    out: dict[str, tuple[Path, dict[str, Any]]] = {}
    for ax in system.axes:
        x0 = system.x0[ax]
        out[f"{ax.lower()}_controller"] = (
            controller_fmu_path(),
            {**system.controllers[ax], "x_meas": x0},
        )
        out[f"{ax.lower()}_plant"] = (
            fmu_path(),
            {**system.plants[ax], "x": x0, "v": 0.0, "solver.tol": system.tolerance},
        )
    return out


def write_xy_osp(system: XYSystem, directory: str | Path) -> Path:
    """``directory/OspSystemStructure.xml`` and both FMUs beside it; returns the XML."""
    sims = [(name, fmu, _typed(fmu, values)) for name, (fmu, values) in components(system).items()]
    conns = [
        (a, ac, b, bc)
        for ax in system.axes
        for c, p in ((f"{ax.lower()}_controller", f"{ax.lower()}_plant"),)
        for a, ac, b, bc in ((p, "x", c, "x_meas"), (c, "u", p, "u"))
    ]
    return osp_structure(directory, system.Ts / system.jacobi_substeps, sims, conns)


def run_libcosim_xy(directory: str | Path, system: XYSystem) -> tuple[dict[str, np.ndarray], float]:
    """libcosim on the OSP structure: each plant's x at t_k (row 0 NaN), and the wall time [s]."""
    from libcosimpy.CosimExecution import CosimExecution  # optional: the test extra
    from libcosimpy.CosimObserver import CosimObserver

    quiet_libcosim()
    ex = CosimExecution.from_osp_config_file(str(directory))
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    idx = {s.name.decode(): s.index for s in ex.slave_infos()}
    plants = {ax: f"{ax.lower()}_plant" for ax in system.axes}
    vr = {
        ax: next(v.reference for v in ex.slave_variables(idx[p]) if v.name.decode() == "x")
        for ax, p in plants.items()
    }
    xs = {ax: np.full(system.n + 1, np.nan) for ax in system.axes}
    wall0 = time.perf_counter()
    for k in range(1, system.n + 1):
        if not ex.step(system.jacobi_substeps):
            raise RuntimeError(f"libcosim: step {k} failed")
        for ax, p in plants.items():
            xs[ax][k] = obs.last_real_values(idx[p], [vr[ax]])[0]
    return xs, time.perf_counter() - wall0


def master_run(system: XYSystem) -> dict[str, np.ndarray]:
    """The same system on the X-Y master (reference as inputs, the harness's convention)."""
    loops = [
        AxisLoop(
            ax, system.plants[ax], {**system.controllers[ax], "ref.source": 0}, system.reference(ax)
        )
        for ax in system.axes
    ]
    res = simulate_axes(loops, Ts=system.Ts, tolerance=system.tolerance)
    return {ax: np.asarray(res[ax]["x"]) for ax in system.axes}
