"""The whole identification (Secs. 2.2-2.4) on a folder of runs -> a model file.

``identify_folder(runs_dir, out)`` loads every run (``feeddrive.data.load_runs``), sorts
them into experiments (:func:`~.classification.classify`: the sidecar's ``kind``, else the
file stem, else the signals; the kinds are those of the experiments the effects declare,
:func:`feeddrive.effects.run_kinds`), and runs the procedures in the order their inputs
require:

1. current loop G(z) from the PRBS run (Eq. 2);
2. K_f(x), F_cg(x) from the constant-speed runs at the speed of the loaded runs
   (Eqs. 3-7; the unloaded runs at that speed are the P = 0 pair);
3. Stribeck curve from every unloaded constant-speed pair (Eqs. 12-13, K_f of step 2);

then the steps the effect modules declare (:attr:`feeddrive.effects.Identification.run`,
:func:`feeddrive.effects.identification_steps`), in their declared order, each handed the
pipeline as its :class:`~feeddrive.effects.steps.IdentificationHost`:

4. mass from the open-loop force run (Eq. 1, maps of step 2, friction of step 3);
5. C from the variable-speed run (Eq. 14, everything above known);
6. pre-rolling from the two periodic runs (Eqs. 15-18);
7. on request (``position_friction=True``; CLI ``--position-friction``), the friction-level
   profile p(x) of ``position_friction`` from every constant-speed run
   (:mod:`.position_friction`: sliding friction against x, linear least squares on the
   B-spline basis; the median of p is 1 and F_s, F_c carry the scale); the model then has
   the effect on.

The model file keeps the paper's model structure (its effect switches); every parameter a
step identifies replaces the paper's value, the others (sample time aside, which comes from
the runs) keep the paper's defaults and are listed in the result and in the model's
description.  A step whose runs are absent is skipped and says so; a step that fails raises
a ValueError naming the step; when every step is skipped (nothing identified) a ValueError
gives each step's reason and how each run was classified, and no model file is written.
With ``truth`` (a model the runs were generated from), the result
(:class:`~.result.IdentificationResult`) holds the table of true versus identified
parameters (:mod:`.truth_table`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..data import Run
from ..effects import EFFECTS, identification_steps, resolve
from ..harness.checked_runs import load_checked_runs
from ..model_file import ModelFile, load_model, paper_model, save_model
from ..physics import CurrentLoop
from ..signals import run_label, sample_time
from .classification import (
    KIND_OF_SHAPE,
    KINDS,
    LOAD_TOL,
    SPEED_TOL,
    classify,
    classify_why,
    group_runs,
    map_and_stribeck_runs,
)
from .current_loop import identify_current_loop
from .position_maps import identify_position_maps
from .result import IdentificationResult, compress_names
from .stribeck import identify_stribeck
from .truth_table import truth_rows

__all__ = [
    "KINDS",
    "KIND_OF_SHAPE",
    "LOAD_TOL",
    "MIN_MAP_SPAN",
    "SPEED_TOL",
    "IdentificationResult",
    "classify",
    "classify_why",
    "group_runs",
    "identify_folder",
    "identify_runs",
    "map_and_stribeck_runs",
]

MIN_MAP_SPAN = 0.075  #: shortest stroke [m] the map runs must share: two magnet pitches


def _as_model(truth: ModelFile | Mapping[str, Any] | str | Path | None) -> ModelFile | None:
    if truth is None or isinstance(truth, ModelFile):
        return truth
    if isinstance(truth, (str, Path)):
        return load_model(truth)
    params = {k: v for k, v in truth.items() if not k.startswith("effects.")}
    effects = {e.id: True for e in EFFECTS if e.switch is None}
    effects.update({e.id: bool(truth.get(e.switch, e.in_paper)) for e in EFFECTS if e.switch})
    return ModelFile(name="truth", effects=effects, parameters=params)


def _step(name: str, fn, *args, **kw):
    try:
        return fn(*args, **kw)
    except ValueError as e:
        raise ValueError(f"identify ({name}): {e}") from None


def identify_runs(
    runs: Sequence[Run],
    truth: ModelFile | Mapping[str, Any] | str | Path | None = None,
    name: str = "identified",
    current_timing: str = "held",
    prerolling_elements: int = 5,
    min_map_span: float = MIN_MAP_SPAN,
    position_friction: bool = False,
    profile_knots: int = 16,
    progress: Callable[[str], None] | None = None,
) -> IdentificationResult:
    """Identify a model from runs (see the module docstring).

    Parameters
    ----------
    runs : the runs of an identification campaign (any order).
    truth : the model the runs came from (file, ModelFile or FMU parameters), for the table.
    name : the model's name.
    current_timing : how a recorded current sample relates to the force (see
        ``feeddrive.physics.held_current``); 'held' is Eq. 2's i[k] at row k, as recorded by
        ``feeddrive.experiments``.
    prerolling_elements : N of the Maxwell-slip model.
    min_map_span : the maps are refused (ValueError) when the runs share a shorter stroke
        [m]: a cubic fitted over a few mm is meaningless over the whole stroke.
    position_friction : also run the steps declared ``on_request`` (the friction-level
        profile p(x), step 7), each switching its effect on when it fits; ``profile_knots``
        knots over the stroke the runs slid over.
    progress : called with each step's name as it starts (a progress bar).
    """
    stage = progress or (lambda name: None)
    placed: list[str] = []
    groups = group_runs(runs, placed)
    base = paper_model()
    res = IdentificationResult(model=base, groups=groups, placement=placed)
    acc = _Collected(dict(base.parameters))
    all_runs = [r for g in groups.values() for r in g]
    if not all_runs:
        raise ValueError("identify: no runs")
    acc.take({"Ts": sample_time(all_runs[0].time, label=run_label(all_runs[0]))})
    stage("current loop")
    dc_gain = _current_loop_step(res, groups, acc, all_runs)
    stage("position maps, Stribeck")
    _maps_and_stribeck_steps(res, groups, acc, dc_gain, min_map_span)
    effects = dict(base.effects)
    host = _Host(res, groups, acc, dc_gain, current_timing, prerolling_elements, profile_knots)
    for e in identification_steps():
        ident = e.identification
        if ident.on_request and not position_friction:
            continue
        assert ident.run is not None
        stage(ident.label)
        fit = ident.run(host)
        setattr(res, ident.step, fit)
        if ident.on_request:
            effects[e.id] = fit is not None
    if not acc.identified - {"Ts"}:
        raise ValueError(
            "identify: nothing identified, every step was skipped: "
            + "; ".join(f"{step}: {why}" for step, why in res.skipped.items())
            + " (runs taken as: "
            + ", ".join(
                f"{r.name or run_label(r)} {kind}" for kind, rs in groups.items() for r in rs
            )
            + ")"
        )
    params = acc.params
    res.defaulted = tuple(k for k in params if k not in acc.identified)
    desc = (
        "identified by feeddrive.identify.pipeline from "
        + ", ".join(sorted({run_label(r) for r in all_runs})[:3])
        + (" ..." if len(all_runs) > 3 else "")
        + "; not identified (paper values): "
        + (compress_names(res.defaulted) or "none")
    )
    res.model = ModelFile(name=name, effects=effects, parameters=params, description=desc)
    res.truth = _as_model(truth)
    if res.truth is not None:
        res.table = truth_rows(res, res.truth)
    return res


@dataclass
class _Collected:
    """The model's parameters as the steps identify them (the paper's until then)."""

    params: dict[str, Any]
    identified: set[str] = field(default_factory=set)

    def take(self, p: Mapping[str, float]) -> None:
        for k, v in p.items():
            if k in self.params:
                self.params[k] = v
                self.identified.add(k)


def _current_loop_step(
    res: IdentificationResult, groups: dict, acc: _Collected, all_runs: list[Run]
) -> float | None:
    """Eq. 2 from the longest PRBS run; returns the DC gain runs without current use."""
    dc_gain = None
    if groups["prbs"]:
        prbs = max(groups["prbs"], key=lambda r: len(r.time))
        res.current_loop = _step("current loop", identify_current_loop, prbs)
        acc.take(res.current_loop.parameters)
        dc_gain = res.current_loop.dc_gain
    else:
        res.skipped["current loop"] = "no PRBS run"
    if any(r.i is None for r in all_runs):
        if dc_gain is None:
            dc_gain = CurrentLoop.from_parameters(acc.params).G1
        res.notes.append(f"runs without a current column use i = G(1) u, G(1) = {dc_gain:.4f} A/V")
    return dc_gain


def _maps_and_stribeck_steps(
    res: IdentificationResult,
    groups: dict,
    acc: _Collected,
    dc_gain: float | None,
    min_map_span: float,
) -> None:
    """Eqs. 6-7 from the loaded constant-speed runs, then Eqs. 12-13 from the unloaded ones."""
    map_runs, strib_runs = map_and_stribeck_runs(groups["constant_speed"])
    if map_runs:
        res.maps = _step("position maps", identify_position_maps, map_runs, dc_gain=dc_gain)
        span = float(res.maps.samples.x[-1] - res.maps.samples.x[0])
        if span < min_map_span:
            raise ValueError(
                f"identify (position maps): the loaded constant-speed runs share only "
                f"{span * 1e3:.1f} mm of stroke; Eqs. 6-7 (a cubic and three harmonics of the "
                f"37.5 mm pitch) need at least {min_map_span * 1e3:g} mm (min_map_span), "
                "better the whole stroke"
            )
        acc.take(res.maps.parameters)
    else:
        res.skipped["position maps"] = "no loaded constant-speed runs"
    if len(strib_runs) >= 12:
        res.stribeck = _step(
            "Stribeck", identify_stribeck, strib_runs, acc.params, acc.params, dc_gain=dc_gain
        )
        acc.take(res.stribeck.parameters)
    else:
        res.skipped["Stribeck"] = (
            f"{len(strib_runs)} unloaded constant-speed runs "
            "(Eq. 12 needs >= 6 speeds in both directions)"
        )


@dataclass
class _Host:
    """The pipeline as the effects' identification steps see it
    (:class:`feeddrive.effects.steps.IdentificationHost`)."""

    res: IdentificationResult
    groups: dict[str, list[Run]]
    acc: _Collected
    dc_gain: float | None
    current_timing: str
    prerolling_elements: int
    profile_knots: int

    @property
    def params(self) -> dict[str, Any]:
        return self.acc.params

    def runs(self, kind: str) -> list[Run]:
        return self.groups[kind]

    def fit(self, label: str, reference: str, *args: Any, **kw: Any) -> Any:
        return _step(label, resolve(reference), *args, **kw)

    def take(self, values: Mapping[str, float]) -> None:
        self.acc.take(values)

    def skip(self, label: str, why: str) -> None:
        self.res.skipped[label] = why

    def note(self, line: str) -> None:
        self.res.notes.append(line)


def identify_folder(
    runs_dir: str | Path,
    out: str | Path | None = None,
    truth: ModelFile | Mapping[str, Any] | str | Path | None = None,
    **kw,
) -> IdentificationResult:
    """Load every run of ``runs_dir``, identify, and write the model file to ``out``.

    ``truth``: optional model the runs were generated from (adds the comparison table).
    Other keywords go to :func:`identify_runs`.  ``out`` is checked before any work
    (:func:`feeddrive.outputs.check_file`: writable, not an input) and replaced atomically.
    """
    inputs = (truth,) if isinstance(truth, (str, Path)) else ()
    side_notes: list[str] = []
    runs = load_checked_runs(runs_dir, out, truth, side_notes)
    res = identify_runs(runs, truth=truth, **kw)
    res.notes[:0] = side_notes
    if out is not None:
        save_model(res.model, out, inputs)
        res.out_path = Path(out)
    return res
