"""The one sidecar schema of the runs our commands write (``run.json`` beside ``run.csv``),
and the reader of every sidecar, ours or another program's.

The recording format lets a sidecar say how an experiment was run; ours always says it the same way::

    {
      "schema": "feeddrive.run/1",
      "experiment": "closed_loop",          what made the run (free text)
      "Ts": 0.0005,                         controller sample time [s]
      "controller": {"type": "pid", ...},   harness.controllers spec, or null (open loop)
      "sensors": {"quantum": 1e-07, "current_noise": 0.005, "seed": 3,
                  "noise_on_stage": true},  harness.sensors.Sensors
      "F_load": 0.0,                        constant pulley load [N] (also the F_load column)
      ...                                   experiment-specific keys (kind, name, speed, ...)
    }

:func:`build_sidecar` makes one, :func:`read_sidecar` reads one back (also a run's
``meta``).  A sidecar is information, not a gate: the reader takes the keys it knows in a
form it understands and lists every other one in ``Sidecar.ignored`` (``controller.law``,
``sensors.gain``, ``Ts`` given as text); a controller the registry cannot build
(:data:`~feeddrive.harness.controllers.CONTROLLERS`) is kept as written in
``Sidecar.foreign_controller`` with the reason in ``Sidecar.notes``, and ``controller`` is
then None (no closed-loop replay).  Only a sidecar that contradicts its CSV is refused
(ValueError naming both values): another sample time (the sidecar's ``Ts`` or the
controller's ``Ts``, against the median step of ``time``, :data:`TS_TOLERANCE`) or another
constant load than a constant ``F_load`` column.  A run without a sidecar reads as no
controller, the default sensors (100 nm scale), no load.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

from ..data import Run, sidecar_path
from .controllers import CONTROLLERS, make_controller
from .references import from_positions
from .sensors import Sensors

SCHEMA = "feeddrive.run/1"
#: The keys the schema defines; every other key is the experiment's own.
FIELDS = ("schema", "experiment", "Ts", "controller", "sensors", "F_load")
#: Top-level keys the tools read besides the schema's fields (in a sidecar without our
#: schema every other top-level key is reported as ignored; in ours they are the
#: experiment's own description).
READ_KEYS = (
    "name",
    "kind",
    "repeat",
    "hold_before_record",
    "prbs_start",
    "force_gain",
    "load",
    "P",
)
#: Largest relative difference between the sidecar's sample time and the CSV's median
#: step that is not a contradiction (clock rounding; another rate differs by far more).
TS_TOLERANCE = 0.01


@dataclass
class Sidecar:
    """A run's sidecar, read.

    Attributes
    ----------
    experiment, Ts, sensors, F_load : the schema's fields (defaults where absent or not
        understood).
    controller : a spec the registry builds, else None (open loop, or ``foreign_controller``).
    extra : the other top-level keys (the experiment's own).
    ignored : dotted names of the keys not used (unknown, or a value not understood).
    notes : what the tools do without, one sentence each.
    foreign_controller : the controller as written when the registry cannot build it.
    meta : the sidecar with only what was used (``controller`` replaced by the usable spec,
        ignored keys left out): what the tools read from ``run.meta`` after
        :func:`read_run_sidecar` with ``clean=True``.
    """

    experiment: str
    Ts: float | None
    controller: dict[str, Any] | None
    sensors: Sensors
    F_load: float = 0.0
    extra: dict[str, Any] = field(default_factory=dict)
    ignored: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    foreign_controller: Any = None
    meta: dict[str, Any] = field(default_factory=dict)

    def note_line(self, where: str = "sidecar") -> str | None:
        """One line naming the ignored keys and what the tools do without, or None."""
        parts = []
        if self.ignored:
            parts.append("ignored " + ", ".join(self.ignored))
        parts += self.notes
        return f"{where}: " + "; ".join(parts) if parts else None


def build_sidecar(
    experiment: str,
    Ts: float,
    controller: Mapping[str, Any] | None,
    sensors: Sensors,
    F_load: float = 0.0,
    **extra: Any,
) -> dict[str, Any]:
    """The sidecar (run ``meta``) of a run made by the harness; ``extra`` keys follow the
    schema's (ValueError when one clashes with them)."""
    clash = set(extra) & set(FIELDS)
    if clash:
        raise ValueError(f"build_sidecar: {sorted(clash)} are schema fields, not extra keys")
    meta: dict[str, Any] = {
        "schema": SCHEMA,
        "experiment": str(experiment),
        "Ts": float(Ts),
        "controller": None if controller is None else dict(controller),
        "sensors": sensors.to_json(),
        "F_load": float(F_load),
    }
    meta.update(extra)
    return meta


def _finite(v: Any) -> bool:
    return not isinstance(v, bool) and isinstance(v, (int, float)) and bool(np.isfinite(v))


def _sensors(obj: Any, side: Sidecar) -> Sensors:
    """The sensors a sidecar's ``sensors`` object gives; keys not understood are ignored."""
    if not isinstance(obj, Mapping):
        side.ignored.append("sensors")
        side.notes.append(
            f"sensors is {type(obj).__name__}, not an object: default sensors "
            f"({Sensors().quantum:g} m scale)"
        )
        return Sensors()
    known = {f.name: f.default for f in fields(Sensors)}
    side.ignored += [f"sensors.{k}" for k in obj if k not in known]
    ok: dict[str, Any] = {}
    for k in known:
        if k not in obj:
            continue
        v = obj[k]
        if k in ("quantum", "current_noise"):
            good = _finite(v) and v >= 0
        elif k == "seed":
            good = isinstance(v, int) and not isinstance(v, bool) and v >= 0
        else:
            good = isinstance(v, bool)
        if good:
            ok[k] = v
        else:
            side.ignored.append(f"sensors.{k}")
            side.notes.append(f"sensors.{k} = {v!r} not understood: {known[k]!r} taken")
    return Sensors(**ok)


def _controller(ctrl: Any, side: Sidecar, Ts: float, x0: float) -> dict[str, Any] | None:
    """The spec of ``ctrl`` the registry builds (unknown keys dropped), else None."""
    if ctrl is None:
        return None
    reason = None
    spec: dict[str, Any] = {}
    if not isinstance(ctrl, Mapping):
        reason = f"controller is {type(ctrl).__name__}, not an object"
    elif ctrl.get("type") not in CONTROLLERS:
        reason = (
            f"controller type {ctrl.get('type')!r} is not one the registry builds "
            f"({', '.join(sorted(CONTROLLERS))})"
        )
    else:
        keys = CONTROLLERS[ctrl["type"]].keys
        unknown = [k for k in ctrl if k not in keys and k != "type"]
        spec = {k: v for k, v in ctrl.items() if k not in unknown}
        try:
            make_controller(spec, from_positions(np.full(8, x0), Ts))
        except (ValueError, TypeError, KeyError, IndexError) as e:
            reason = str(e)
        else:
            side.ignored += [f"controller.{k}" for k in unknown]
            return spec
        if unknown:
            reason += f" (keys not known to type {ctrl['type']!r}: {', '.join(unknown)})"
    side.foreign_controller = ctrl
    side.ignored.append("controller")
    side.notes.append(
        f"{reason}: no closed-loop replay (the run serves what needs no "
        "controller: force residual, identification, diagnosis)"
    )
    return None


def read_sidecar(
    meta: Mapping[str, Any] | None, where: str = "sidecar", run: Run | None = None
) -> Sidecar:
    """Read a sidecar (a run's ``meta``); with ``run``, checked against its CSV.

    Never refuses for a key it does not know or a value it does not understand (see the
    module docstring: they are listed in ``ignored`` and ``notes``).  ValueError naming
    ``where`` and both values when the sidecar contradicts ``run`` (sample time, a constant
    load).
    """
    meta = dict(meta or {})
    side = Sidecar(experiment="", Ts=None, controller=None, sensors=Sensors())
    schema = meta.get("schema")
    if schema is not None and schema != SCHEMA:
        side.notes.append(f"schema {schema!r} is not {SCHEMA!r}: read for the keys they share")
    ours = schema == SCHEMA
    csv_Ts = run.Ts if run is not None and run.n >= 2 else None
    Ts = meta.get("Ts")
    if Ts is not None:
        if _finite(Ts) and csv_Ts is not None and abs(Ts - csv_Ts) > TS_TOLERANCE * csv_Ts:
            raise ValueError(
                f"{where}: Ts = {Ts!r} s contradicts the CSV, whose time column "
                f"steps {csv_Ts:.6g} s"
            )
        if _finite(Ts) and Ts > 0:
            side.Ts = float(Ts)
        else:
            side.ignored.append("Ts")
            side.notes.append(f"Ts = {Ts!r} is not a sample time: the CSV's step taken")
    ctrl = meta.get("controller")
    if (
        isinstance(ctrl, Mapping)
        and "Ts" in ctrl
        and _finite(ctrl["Ts"])
        and csv_Ts is not None
        and abs(ctrl["Ts"] - csv_Ts) > TS_TOLERANCE * csv_Ts
    ):
        raise ValueError(
            f"{where}: controller Ts = {ctrl['Ts']!r} s contradicts the CSV, whose "
            f"time column steps {csv_Ts:.6g} s"
        )
    Ts_ctrl = side.Ts or csv_Ts or 5e-4
    x0 = float(
        run.x_ref[0]
        if run is not None and run.x_ref is not None
        else run.x[0]
        if run is not None
        else 0.15
    )
    side.controller = _controller(ctrl, side, Ts_ctrl, x0)
    if "sensors" in meta:
        side.sensors = _sensors(meta["sensors"], side)
    F_load = meta.get("F_load", 0.0)
    if _finite(F_load):
        side.F_load = float(F_load)
        col = None if run is None else run.F_load
        if (
            "F_load" in meta
            and col is not None
            and np.ptp(col) == 0
            and abs(col[0] - F_load) > 1e-9 * max(1.0, abs(F_load))
        ):
            raise ValueError(
                f"{where}: F_load = {F_load!r} N contradicts the CSV, whose F_load "
                f"column is {float(col[0])!r} N throughout"
            )
    else:
        side.ignored.append("F_load")
        side.notes.append(
            f"F_load = {F_load!r} is not a load [N]: "
            + (
                "the F_load column taken"
                if run is not None and run.F_load is not None
                else "no load taken"
            )
        )
    g = meta.get("force_gain")
    if g is not None and not (_finite(g) and g > 0):
        side.ignored.append("force_gain")
        side.notes.append(
            f"force_gain = {g!r} is not a gain > 0 [N/V]: the model's current "
            "loop taken for runs without current"
        )
    side.experiment = str(meta.get("experiment", ""))
    side.extra = {k: v for k, v in meta.items() if k not in FIELDS}
    if not ours:
        side.ignored += [k for k in side.extra if k not in READ_KEYS]
    dropped = {k for k in side.ignored if "." not in k}
    clean = {k: v for k, v in meta.items() if k not in dropped}
    if "controller" in meta:
        clean["controller"] = side.controller
    if isinstance(meta.get("sensors"), Mapping):
        clean["sensors"] = {
            k: v for k, v in meta["sensors"].items() if f"sensors.{k}" not in side.ignored
        }
    side.meta = clean
    return side


def read_run_sidecar(run: Run, where: str | None = None, clean: bool = True) -> Sidecar:
    """:func:`read_sidecar` of ``run.meta`` checked against the run's CSV; with ``clean``
    the run's ``meta`` becomes ``Sidecar.meta`` (what was used), so that every tool reads
    the same understood keys."""
    if where is None:
        where = (
            str(sidecar_path(run.path)) if run.path is not None else f"{run.name or 'run'}: sidecar"
        )
    side = read_sidecar(run.meta, where=where, run=run)
    if clean:
        run.meta = dict(side.meta)
    return side
