"""What a plan is: its runs (reference columns, sidecar, load, purpose) in order, and what
each run group identifies."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...effects import experiments
from ...harness.references import Reference
from ...harness.sidecar import SCHEMA
from ..recording import HOLD
from .limits import Limits

#: what each run group identifies (``identify``'s steps), for the plan page: the experiments
#: the effects declare (:func:`feeddrive.effects.experiments`), in campaign order
IDENTIFIES: dict[str, str] = {x.page_group: x.identifies for x in experiments()}
#: the same, in a few words (the page's table of runs)
IDENTIFIES_SHORT: dict[str, str] = {x.page_group: x.short for x in experiments()}
#: the sidecar kind of each run group
KIND_OF_GROUP: dict[str, str] = {x.page_group: x.kind for x in experiments()}


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


def run_sidecar(
    kind: str,
    Ts: float,
    controller: Mapping[str, Any] | None,
    load: float,
    closed_loop: bool,
    /,
    **extra: Any,
) -> dict[str, Any]:
    """The sidecar of one run (:mod:`feeddrive.harness.sidecar` form): closed-loop runs
    hold before recording."""
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


def closed_loop_columns(ref: Reference, u_add: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The reference CSV's columns of a closed-loop run: time, x_ref [, u_add]."""
    cols = {"time": ref.time, "x_ref": ref.x}
    if u_add is not None:
        cols["u_add"] = u_add
    return cols
