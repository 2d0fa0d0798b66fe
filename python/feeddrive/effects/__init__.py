"""The effect catalogue (docs/effects.md) as a registry: one module per effect, each
exporting one :class:`~feeddrive.effects.effect.Effect` named ``EFFECT``, and the one list
:data:`EFFECTS` in catalogue order.  Every other list of effects in the package is derived
from it; docs/adding-an-effect.md gives the recipe for a new one.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from . import (
    asymmetric_friction,
    cogging_aperiodic,
    cogging_periodic,
    compliance,
    current_dynamics,
    frictional_lag,
    mass,
    offset_force,
    position_friction,
    prerolling,
    ripple_aperiodic,
    ripple_periodic,
    stribeck,
    viscous,
)
from .effect import (
    SHAPES,
    Candidate,
    Effect,
    Experiment,
    Identification,
    Parameter,
    ReportFigure,
    Rule,
    Structure,
    is_on,
    nested,
    reference,
    resolve,
    selected,
    slot_count,
    switched_off,
)

#: Every effect of the catalogue, in catalogue order (the first nine are the paper's model).
EFFECTS: tuple[Effect, ...] = (
    current_dynamics.EFFECT,
    cogging_periodic.EFFECT,
    cogging_aperiodic.EFFECT,
    ripple_periodic.EFFECT,
    ripple_aperiodic.EFFECT,
    stribeck.EFFECT,
    viscous.EFFECT,
    prerolling.EFFECT,
    frictional_lag.EFFECT,
    mass.EFFECT,
    offset_force.EFFECT,
    asymmetric_friction.EFFECT,
    position_friction.EFFECT,
    compliance.EFFECT,
)
#: Effect by id.
BY_ID: dict[str, Effect] = {e.id: e for e in EFFECTS}


def effect(effect_id: str) -> Effect:
    """The effect ``effect_id`` of the catalogue.

    Raises
    ------
    KeyError : not an id of the catalogue (the message lists the ids).
    """
    try:
        return BY_ID[effect_id]
    except KeyError:
        raise KeyError(
            f"{effect_id!r} is not an effect of the catalogue: allowed " + ", ".join(BY_ID)
        ) from None


def effect_ids() -> list[str]:
    """Every id of the catalogue, in catalogue order."""
    return [e.id for e in EFFECTS]


def switchable() -> list[Effect]:
    """The effects with an FMU switch ``effects.<id>`` (all but the always-on mass)."""
    return [e for e in EFFECTS if e.switchable]


def apply_switches(values: Mapping[str, Any]) -> dict[str, Any]:
    """FMU-named ``values`` with every switched-off effect's :attr:`Effect.off` rules applied
    (catalogue order; a missing switch counts as on): the values the plant's physics uses."""
    return switched_off(values, EFFECTS)


def broken_rule(values: Mapping[str, Any]) -> str | None:
    """The FMU's message for the first effect rule the FMU-named ``values`` (every parameter)
    break, else None: every :attr:`Effect.compile_rule`, then every :attr:`Effect.check_rule`,
    in catalogue order (the order of the FMU's effect table)."""
    effective = apply_switches(values)
    for rules in ([(e, e.compile_rule) for e in EFFECTS], [(e, e.check_rule) for e in EFFECTS]):
        for e, rule in rules:
            msg = None if rule is None else rule(values, effective, is_on(e, values))
            if msg is not None:
                return msg
    return None


def structure_on(values: Mapping[str, Any], structure: Structure) -> bool:
    """Whether the plant structure ``structure`` is on for FMU-named ``values``: the switch
    of the effect that selects it (a missing switch takes the FMU's default)."""
    return selected(values, structure, EFFECTS)


def structure_off(structure: Structure) -> dict[str, bool]:
    """The switch setting that turns the plant structure ``structure`` off, FMU-named.

    Raises
    ------
    LookupError : no switchable effect selects ``structure``.
    """
    for e in EFFECTS:
        if e.structure is structure and e.switch is not None:
            return {e.switch: False}
    raise LookupError(f"no effect switch selects the plant structure {structure.name}")


def paper_scenarios() -> dict[str, dict[str, bool]]:
    """The paper's Sec. 3 scenarios that switch one effect off, by label: each effect's
    :attr:`Effect.scenario` with its switch off, in catalogue order."""
    return {e.scenario: {e.switch: False} for e in EFFECTS if e.scenario and e.switch is not None}


def nesting() -> dict[str, str]:
    """Each effect whose diagnosis candidate reduces to another's in a limit, by id: the
    other's id (:func:`~feeddrive.effects.effect.nested` of the catalogue)."""
    return nested(EFFECTS)


def emps_baseline() -> list[str]:
    """The ids of the effects on in the EMPS benchmark's rigid baseline model."""
    return [e.id for e in EFFECTS if e.candidate.emps_baseline]


def position_map_effects() -> dict[str, tuple[str, str]]:
    """The ids of the (periodic, aperiodic) parts of each position map (Eqs. 6-7)."""
    parts: dict[str, dict[str, str]] = {}
    for e in EFFECTS:
        if e.position_map is not None:
            name, part = e.position_map
            parts.setdefault(name, {})[part] = e.id
    return {name: (p["periodic"], p["aperiodic"]) for name, p in parts.items()}


def identification_steps() -> list[Effect]:
    """The effects whose identification step runs in its module
    (:attr:`Identification.run`), in pipeline order (:attr:`Identification.order`)."""
    steps = [e for e in EFFECTS if e.identification.run is not None]
    return sorted(steps, key=lambda e: e.identification.order)


def truth_row_steps() -> list[Effect]:
    """The effects that give the rows of their step in the table of true versus identified
    parameters (:attr:`Identification.truth`), in pipeline order."""
    steps = [e for e in EFFECTS if e.identification.truth]
    return sorted(steps, key=lambda e: e.identification.order)


def owner(parameter: str) -> Effect:
    """The effect that owns the FMU parameter ``parameter`` (:attr:`Effect.parameters`).

    Raises
    ------
    LookupError : no effect owns it.
    """
    for e in EFFECTS:
        if parameter in e.parameter_names:
            return e
    raise LookupError(f"no effect owns the parameter {parameter}")


def report_figures() -> list[tuple[Effect, ReportFigure]]:
    """Every figure of the identification report the effects declare, with its effect, in
    page order (:attr:`ReportFigure.order`)."""
    figs = [(e, f) for e in EFFECTS for f in e.figures]
    return sorted(figs, key=lambda ef: ef[1].order)


def figure_owner(fn: Callable[..., Any]) -> Effect:
    """The effect that declares the report figure drawn by ``fn`` (:attr:`Effect.figures`).

    Raises
    ------
    LookupError : no effect declares it.
    """
    ref = reference(fn)
    for e, f in report_figures():
        if f.figure == ref:
            return e
    raise LookupError(f"no effect declares the report figure {ref}")


def experiments() -> list[Experiment]:
    """Every experiment of the identification campaign the effects declare, in campaign
    order (:attr:`Experiment.order`)."""
    return sorted((x for e in EFFECTS for x in e.experiments), key=lambda x: x.order)


def experiment_running(fn: Callable[..., Any]) -> Experiment:
    """The experiment whose runs the function ``fn`` simulates (:attr:`Experiment.runs`).

    Raises
    ------
    LookupError : no effect declares an experiment run by ``fn``.
    """
    ref = reference(fn)
    for x in experiments():
        if x.runs == ref:
            return x
    raise LookupError(f"no effect declares an experiment run by {ref}")


@dataclass(frozen=True)
class RunKind:
    """A kind of run (the sidecar's ``kind``) as ``identify`` sorts runs: the signal shape
    that shows it, the file stems that name it, and what it is used for."""

    kind: str
    shape: str
    file_pattern: str
    uses: str


def run_kinds() -> dict[str, RunKind]:
    """The kinds of run of the campaign's experiments, by kind, in campaign order: shape and
    file pattern of the first experiment of each kind that declares them, the uses of every
    experiment of the kind joined."""
    out: dict[str, RunKind] = {}
    for x in experiments():
        k = out.get(x.kind)
        if k is None:
            out[x.kind] = RunKind(x.kind, x.shape, x.file_pattern, x.uses)
        else:
            out[x.kind] = RunKind(
                x.kind,
                k.shape or x.shape,
                k.file_pattern or x.file_pattern,
                " and ".join(u for u in (k.uses, x.uses) if u),
            )
    for k in out.values():
        if k.shape not in SHAPES or not k.file_pattern:
            raise ValueError(f"run kind {k.kind}: no experiment declares its shape and file stem")
    return out


__all__ = [
    "BY_ID",
    "Candidate",
    "EFFECTS",
    "Effect",
    "Experiment",
    "RunKind",
    "SHAPES",
    "Identification",
    "Parameter",
    "ReportFigure",
    "Rule",
    "Structure",
    "apply_switches",
    "broken_rule",
    "effect",
    "effect_ids",
    "experiment_running",
    "experiments",
    "figure_owner",
    "report_figures",
    "identification_steps",
    "owner",
    "truth_row_steps",
    "is_on",
    "paper_scenarios",
    "emps_baseline",
    "nested",
    "nesting",
    "position_map_effects",
    "reference",
    "run_kinds",
    "resolve",
    "selected",
    "slot_count",
    "structure_off",
    "structure_on",
    "switchable",
    "switched_off",
]
