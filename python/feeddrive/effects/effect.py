"""What the project knows of one effect of the catalogue, as data: :class:`Effect`.

Every effect module of :mod:`feeddrive.effects` exports one ``EFFECT``; the package's
``EFFECTS`` lists them in catalogue order.  Code elsewhere refers to the effect's Python
parts (its physics term, its identification, its diagnosis candidate) by a reference
``"module:attribute"`` (dotted attributes allowed) that :func:`resolve` imports; a test
resolves every reference of the registry, so none can go stale.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from enum import Enum
from typing import Any

from .steps import IdentificationHost


@dataclass(frozen=True)
class Parameter:
    """One FMU parameter of an effect: its name (``name[j]`` for a slot array), SI unit and
    the rule the FMU and the Python twin check on it ("" when only the declared range)."""

    name: str
    unit: str
    rule: str = ""


@dataclass(frozen=True)
class Identification:
    """How the identification (``feeddrive identify``) finds the effect.

    ``step``: the pipeline step that fits it (an attribute of ``IdentificationResult``), or
    "" when the pipeline has no step for it (``fit`` then says which function fits it, e.g.
    within another effect's step, or the diagnosis does); ``fit``: a reference to the
    function that fits it, or "";
    ``how``: one line for the docs and the report;
    ``label``: the step's name in progress, messages and the skipped steps ("" : ``step``);
    ``order``: the step's place in the pipeline (ascending; every effect of a shared step
    gives it), 0 for no step;
    ``run``: the step, a function of the pipeline's
    :class:`~feeddrive.effects.steps.IdentificationHost` returning the fit (the result's
    attribute ``step``) or None when skipped; None when the pipeline runs the step itself;
    ``on_request``: the step runs only when asked for (``identify --position-friction``) and
    switches the effect on when it fits;
    ``truth``: a reference to the function ``(fit, truth model, result) -> rows`` of the
    table of true versus identified parameters for the step ("" : no rows; one effect of a
    shared step gives it).
    """

    step: str
    fit: str
    how: str
    label: str = ""
    order: int = 0
    run: Step | None = None
    on_request: bool = False
    truth: str = ""


@dataclass(frozen=True)
class Candidate:
    """The effect as a diagnosis candidate (``feeddrive diagnose``).

    ``builder``: a reference to the function that builds its variants from a diagnosis
    context (``candidate`` of the effect's module, :mod:`feeddrive.effects.candidate`);
    ``perturbs``: the parameters it adds or corrects; ``label``: how its variants are named
    (the variant's label follows the effect id in the verdict); ``limit``: the parameters of
    the family this one reduces to in a limit (a load on a spring is a change of the mass
    ``m`` far below its resonance), whose candidate perturbs them: the diagnosis ranks this
    family only when held-out data show it beyond that one (:func:`nested`);
    ``emps_baseline``: on in the EMPS benchmark's rigid baseline model (IDIM-LS: mass,
    viscous and Coulomb friction, an offset).
    """

    builder: str
    perturbs: tuple[str, ...]
    label: str
    limit: tuple[str, ...] = ()
    emps_baseline: bool = False


@dataclass(frozen=True)
class Effect:
    """One effect of the catalogue (docs/effects.md).

    Attributes
    ----------
    id : the catalogue id, the key of a model file's ``effects``.
    switch : its FMU switch (``effects.<id>``), None when the effect is always on (mass).
    in_paper : on in the paper's model (Villegas et al. 2014).
    description : one line, as the switch's description in ``modelDescription.xml``.
    parameters : the FMU parameters it owns.
    physics : reference to the Python twin of its force or state term.
    identification : how identification fits it.
    candidate : how diagnosis tries it.
    report : the lines of the identification report that show it.
    position_map : ("cogging" | "ripple", "periodic" | "aperiodic") for a part of a
        position map (Eqs. 6-7), else None.
    off : what switching the effect off does to the parameters, (name, value) pairs: a
        number, or the name of the parameter whose value it takes (``name[j]``: every slot);
        empty when off changes the model's structure instead (no values express it).
    structure : the structural option of the compiled plant its switch selects (a
        :class:`Structure`), None when its ``off`` rule's values say all.
    compile_rule : a :data:`Rule` the plant's compilation checks (``compile_rule`` of every
        effect in catalogue order, as the FMU's effect entries compile), or None.
    check_rule : a :data:`Rule` of combination checked after every ``compile_rule``
        (catalogue order, as the FMU's entries' checks), or None.
    scenario : the label of the paper's scenario (Sec. 3, Fig. 14) that switches the effect
        off, "" when none does.
    experiments : the experiments of the identification campaign that identify it
        (:class:`Experiment`; an experiment shared by several effects is declared by one).
    figures : the figures of the identification report that show its step's fit
        (:class:`ReportFigure`; a figure of a shared step is declared by one effect).
    """

    id: str
    switch: str | None
    in_paper: bool
    description: str
    parameters: tuple[Parameter, ...]
    physics: str
    identification: Identification
    candidate: Candidate
    report: tuple[str, ...]
    position_map: tuple[str, str] | None = None
    off: tuple[tuple[str, float | str], ...] = ()
    structure: Structure | None = None
    compile_rule: Rule | None = None
    check_rule: Rule | None = None
    scenario: str = ""
    experiments: tuple[Experiment, ...] = ()
    figures: tuple[ReportFigure, ...] = ()

    def __post_init__(self) -> None:
        if self.switch is not None and self.switch != f"effects.{self.id}":
            raise ValueError(
                f"effect {self.id}: switch {self.switch!r}, allowed 'effects.{self.id}' or None"
            )
        if self.position_map is not None and (
            self.position_map[0] not in ("cogging", "ripple")
            or self.position_map[1] not in ("periodic", "aperiodic")
        ):
            raise ValueError(
                f"effect {self.id}: position_map {self.position_map!r}, allowed "
                "(cogging|ripple, periodic|aperiodic)"
            )

    @property
    def switchable(self) -> bool:
        """The effect has an FMU switch."""
        return self.switch is not None

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """The names of :attr:`parameters`."""
        return tuple(p.name for p in self.parameters)


def _slots(name: str, values: Mapping[str, object]) -> list[str]:
    """The names ``name`` stands for among ``values`` (every slot of ``name[j]``)."""
    if not name.endswith("[j]"):
        return [name]
    stem = name[:-2]
    return [
        k for k in values if k.startswith(stem) and k.endswith("]") and k[len(stem) : -1].isdigit()
    ]


def switched_off(values: Mapping[str, Any], effects: Iterable[Effect]) -> dict[str, Any]:
    """``values`` (FMU-named) with the :attr:`Effect.off` rules of every effect of ``effects``
    whose switch is false applied, in the order given (a missing switch counts as on)."""
    out = dict(values)
    for e in effects:
        if e.switch is None or bool(values.get(e.switch, True)):
            continue
        for name, value in e.off:
            for slot in _slots(name, out):
                out[slot] = out[value] if isinstance(value, str) else value
    return out


def resolve(reference: str) -> object:
    """The object a reference ``"package.module:attr.attr"`` names (imports the module).

    Raises
    ------
    ValueError : the reference is not of that form.
    ImportError, AttributeError : the module or attribute does not exist.
    """
    module, sep, attr = reference.partition(":")
    if not sep or not module or not attr:
        raise ValueError(f"effect reference {reference!r}: allowed 'package.module:attribute'")
    obj: object = importlib.import_module(module)
    for part in attr.split("."):
        obj = getattr(obj, part)
    return obj


class Structure(Enum):
    """A structural option of the compiled plant that one effect's switch selects
    (:attr:`Effect.structure`); the value says what it is on and what replaces it off."""

    CURRENT_FILTER = "the current loop's dynamics G(z), Eq. 2 (off: i = G(1) u at once)"
    SLIP_ELEMENTS = "the GMS's Maxwell-slip elements (off: static friction, Eq. 12)"
    LEVEL_PROFILE = "the friction level's profile p(x) along the stroke (off: p = 1)"
    LOAD_ON_SPRING = "a load on a spring-damper on the slide (off: one rigid moving mass)"


#: A rule of an effect on the plant's parameters (:attr:`Effect.compile_rule`,
#: :attr:`Effect.check_rule`): from the FMU-named values as given, the same values with every
#: switched-off effect's ``off`` rule applied (:func:`switched_off`) and whether the effect is
#: on, the FMU's message for the first rule broken, else None.
Rule = Callable[[Mapping[str, Any], Mapping[str, Any], bool], str | None]


def is_on(e: Effect, values: Mapping[str, Any]) -> bool:
    """Whether ``e`` is on for FMU-named ``values``: its switch's value, the FMU's default
    when the switch is missing (on for an effect of the paper's model); always for mass."""
    return e.switch is None or bool(values.get(e.switch, e.in_paper))


def selected(values: Mapping[str, Any], structure: Structure, effects: Iterable[Effect]) -> bool:
    """Whether ``structure`` is on for FMU-named ``values``: the switch of the effect of
    ``effects`` that selects it (:func:`is_on`).

    Raises
    ------
    LookupError : no effect of ``effects`` selects ``structure``.
    """
    for e in effects:
        if e.structure is structure:
            return is_on(e, values)
    raise LookupError(f"no effect selects the plant structure {structure.name}")


def slot_count(name: str, values: Mapping[str, Any]) -> int:
    """How many slots ``name[j]`` the FMU-named ``values`` hold (the FMU's array size when
    ``values`` hold every parameter)."""
    return len(_slots(name, values))


def nested(effects: Iterable[Effect]) -> dict[str, str]:
    """For each effect of ``effects`` whose candidate family reduces to another's in a limit
    (:attr:`Candidate.limit`), the id of that other: the effect whose candidate perturbs
    exactly those parameters.

    Raises
    ------
    ValueError : no effect's candidate perturbs a declared limit.
    """
    effects = list(effects)
    by_perturbs = {e.candidate.perturbs: e.id for e in effects}
    out: dict[str, str] = {}
    for e in effects:
        if not e.candidate.limit:
            continue
        if e.candidate.limit not in by_perturbs:
            raise ValueError(
                f"effect {e.id}: candidate limit {e.candidate.limit!r} is what no effect's "
                "candidate perturbs"
            )
        out[e.id] = by_perturbs[e.candidate.limit]
    return out


#: An effect's identification step: from the pipeline's host, the fit or None (skipped).
Step = Callable[[IdentificationHost], Any]


#: What the signals of a run show, the recognisable form of each kind of run (the
#: identification's fallback when a run has no sidecar ``kind``): the position held while u
#: excites; no position reference (open loop); reversing; monotonic at a steady speed;
#: monotonic without one.
SHAPES = ("held", "open_loop", "reversing", "steady", "varying")


@dataclass(frozen=True)
class Experiment:
    """An experiment of the identification campaign, declared by the effect it identifies
    (:attr:`Effect.experiments`).  Its names are the recording format users' files carry
    (docs/data-format.md): written once here, handed to the generic experiment code.

    Attributes
    ----------
    group : the campaign's group (``feeddrive experiments``), the stem of its jobs' labels and
        so of their noise seeds.
    kind : the sidecar's ``kind`` of its runs (``identify`` sorts runs by it).
    order : its place in the campaign and in the plan (ascending).
    runs : reference to the function that simulates its runs (:mod:`feeddrive.experiments`).
    campaign : reference to the campaign's builder of its jobs, ``(experiment, quick) -> jobs``.
    plan : reference to the plan's builder of its runs, ``(builder, experiment) -> None``.
    identifies : what it identifies, one line of the plan page; short : the same in a few words.
    stem : the stem of its run names where the experiment names them itself ("" else).
    plan_group : its group on the plan page and in the plan's sidecars ("" : ``group``).
    shape : the :data:`SHAPES` entry its runs' signals show ("" : a kind another experiment
        declares first).
    file_pattern : the regular expression a recording's file stem of this kind starts with
        ("" : as ``shape``).
    uses : what ``identify`` uses runs of its kind for.
    """

    group: str
    kind: str
    order: int
    runs: str
    campaign: str
    plan: str
    identifies: str
    short: str
    stem: str = ""
    plan_group: str = ""
    shape: str = ""
    file_pattern: str = ""
    uses: str = ""

    def __post_init__(self) -> None:
        if self.shape and self.shape not in SHAPES:
            raise ValueError(
                f"experiment {self.group}: shape {self.shape!r}, allowed " + ", ".join(SHAPES)
            )

    @property
    def page_group(self) -> str:
        """Its group on the plan page and in the plan's sidecars."""
        return self.plan_group or self.group


def reference(fn: Callable[..., Any]) -> str:
    """The reference ``"module:qualname"`` of a function (what :func:`resolve` imports)."""
    return f"{fn.__module__}:{fn.__qualname__}"


@dataclass(frozen=True)
class ReportFigure:
    """A figure of the identification report (``feeddrive report``) that shows an effect's
    identification step (:attr:`Effect.figures`): drawn when the step's fit exists.

    ``figure``: reference to the function ``(identification result) -> Figure``;
    ``stem``: the file stem it is saved under; ``caption``: its caption; ``order``: its place
    on the report page (ascending).
    """

    figure: str
    stem: str
    caption: str
    order: int
