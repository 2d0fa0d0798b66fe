"""The one sidecar schema of the runs our commands write (``run.json`` beside ``run.csv``).

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
``meta``), checking the fields the harness uses; a run without a sidecar reads as no
controller, ideal sensors taken as the 100 nm default, no load.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .sensors import Sensors

SCHEMA = "feeddrive.run/1"
#: The keys the schema defines; every other key is the experiment's own.
FIELDS = ("schema", "experiment", "Ts", "controller", "sensors", "F_load")


@dataclass
class Sidecar:
    """A run's sidecar, read: the schema's fields and the experiment's own keys (``extra``)."""

    experiment: str
    Ts: float | None
    controller: dict[str, Any] | None
    sensors: Sensors
    F_load: float = 0.0
    extra: dict[str, Any] = field(default_factory=dict)


def build_sidecar(experiment: str, Ts: float, controller: Mapping[str, Any] | None,
                  sensors: Sensors, F_load: float = 0.0, **extra: Any) -> dict[str, Any]:
    """The sidecar (run ``meta``) of a run made by the harness; ``extra`` keys follow the
    schema's (ValueError when one clashes with them)."""
    clash = set(extra) & set(FIELDS)
    if clash:
        raise ValueError(f"build_sidecar: {sorted(clash)} are schema fields, not extra keys")
    meta: dict[str, Any] = {"schema": SCHEMA, "experiment": str(experiment), "Ts": float(Ts),
                            "controller": None if controller is None else dict(controller),
                            "sensors": sensors.to_json(), "F_load": float(F_load)}
    meta.update(extra)
    return meta


def read_sidecar(meta: Mapping[str, Any] | None, where: str = "sidecar") -> Sidecar:
    """Read a run's ``meta`` by the schema; ValueError naming ``where`` and the field.

    A sidecar without ``schema`` (someone else's run) is read for what it has: the
    controller, Ts, sensors and F_load when present, the defaults otherwise.
    """
    meta = dict(meta or {})
    schema = meta.get("schema")
    if schema is not None and schema != SCHEMA:
        raise ValueError(f"{where}: schema {schema!r} is not {SCHEMA!r}")
    Ts = meta.get("Ts")
    if Ts is not None:
        if isinstance(Ts, bool) or not isinstance(Ts, (int, float)) or not (np.isfinite(Ts) and Ts > 0):
            raise ValueError(f"{where}: Ts = {Ts!r} must be a number > 0 [s]")
        Ts = float(Ts)
    ctrl = meta.get("controller")
    if ctrl is not None and not isinstance(ctrl, Mapping):
        raise ValueError(f"{where}: controller must be an object or null, got "
                         f"{type(ctrl).__name__}")
    if ctrl is not None and "type" not in ctrl:
        raise ValueError(f"{where}: controller has no 'type'")
    sensors = Sensors.from_json(meta["sensors"], f"{where}: sensors") if "sensors" in meta \
        else Sensors()
    F_load = meta.get("F_load", 0.0)
    if isinstance(F_load, bool) or not isinstance(F_load, (int, float)) or not np.isfinite(F_load):
        raise ValueError(f"{where}: F_load = {F_load!r} must be a finite number [N]")
    return Sidecar(experiment=str(meta.get("experiment", "")), Ts=Ts,
                   controller=None if ctrl is None else dict(ctrl), sensors=sensors,
                   F_load=float(F_load), extra={k: v for k, v in meta.items() if k not in FIELDS})
