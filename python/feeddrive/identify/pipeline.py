"""The whole identification (Secs. 2.2-2.4) on a folder of runs -> a model file.

``identify_folder(runs_dir, out)`` loads every run (``feeddrive.data.load_runs``), sorts
them into experiments (:func:`classify`: the sidecar's ``kind``, else the file stem, else
the signals; the kinds are those of the experiments the effects declare,
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
With ``truth`` (a model the runs were generated from), the result holds the table of true
versus identified parameters (:mod:`.truth_table`).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..data import Run, run_stem
from ..effects import EFFECTS, identification_steps, resolve, run_kinds
from ..harness.checked_runs import load_checked_runs
from ..model_file import ModelFile, load_model, paper_model, save_model
from ..physics import CurrentLoop, run_load_mean
from ..signals import run_label, sample_time
from ._signals import steady_segment
from .attraction import AttractionFit
from .current_loop import CurrentLoopFit, identify_current_loop
from .mass import MassFit
from .position_friction import PositionFrictionFit
from .position_maps import PositionMapsFit, identify_position_maps
from .prerolling import PrerollingFit
from .stribeck import StribeckFit, identify_stribeck
from .truth_table import TruthRow, format_rows, truth_rows

#: Experiment kinds (the sidecar's ``kind``) and what each is used for: the kinds of the
#: experiments the effects declare (:func:`feeddrive.effects.run_kinds`), in campaign order.
KINDS: dict[str, str] = {k.kind: k.uses for k in run_kinds().values()}
#: The file stems (regular expressions at the stem's start) that name each kind.
_STEMS = tuple((k.kind, k.file_pattern) for k in run_kinds().values())
#: The kind whose runs' signals show each shape (:data:`feeddrive.effects.SHAPES`).
KIND_OF_SHAPE: dict[str, str] = {k.shape: k.kind for k in run_kinds().values()}
MIN_MAP_SPAN = 0.075  #: shortest stroke [m] the map runs must share: two magnet pitches
LOAD_TOL = 0.5  #: loads closer than this [N] are the same load (as position_maps)
SPEED_TOL = 0.1  #: relative speed difference within which runs share a speed


def classify(run: Run) -> str:
    """The experiment kind of a run (:func:`classify_why` without the reason)."""
    return classify_why(run)[0]


def _crossings(u: np.ndarray) -> int:
    """How often ``u`` crosses its mean (0 for a constant signal)."""
    dev = u - np.mean(u)
    return int(np.count_nonzero(np.diff(np.sign(dev[dev != 0]))))


def _shape(run: Run) -> tuple[str | None, str]:
    """The shape the signals show (:data:`feeddrive.effects.SHAPES`), or None, and why (every
    test fails for a constant signal)."""
    x = np.asarray(run.x, dtype=float)
    u = np.asarray(run.u, dtype=float)
    span = float(np.ptp(x))
    if span < 1e-4:
        sw = _crossings(u)
        moving_i = run.i is None or np.ptp(run.i) > 0
        if span > 0 and sw >= 10 and moving_i:
            return "held", f"x held within {span * 1e6:.1f} um, u excites ({sw} mean crossings)"
        return None, (
            f"x {'constant' if span == 0 else f'held within {span * 1e6:.1f} um'}, u "
            f"with {sw} mean crossings"
            + ("" if moving_i else ", i constant")
            + ": not a PRBS excitation (x must move a little, u cross its mean "
            ">= 10 times)"
        )
    if np.ptp(u) == 0:
        return None, "u is constant: no experiment of Secs. 2.2-2.4"
    if run.x_ref is None:
        return "open_loop", f"no x_ref column (open loop), x spans {span * 1e3:.2f} mm"
    dx = np.diff(x)
    back = min(np.sum(dx[dx > 0]), -np.sum(dx[dx < 0]))
    if back > 0.3 * span:
        return (
            "reversing",
            f"x reverses ({back * 1e6:.0f} um back over a {span * 1e6:.0f} um span)",
        )
    Ts = sample_time(run.time, label=run_label(run))
    seg, v = steady_segment(x, Ts, label=run_label(run))
    share = (seg.stop - seg.start) / len(x)
    if share > 0.3:
        return (
            "steady",
            f"monotonic, steady speed {abs(v) * 1e3:.3g} mm/s over {share:.0%} of the run",
        )
    return "varying", f"monotonic, no steady speed over 30 % of the run ({share:.0%})"


def _by_signals(run: Run) -> tuple[str | None, str]:
    """The kind the signals show (:data:`KIND_OF_SHAPE`), or None, and why."""
    shape, why = _shape(run)
    return (None if shape is None else KIND_OF_SHAPE[shape]), why


def classify_why(run: Run) -> tuple[str, str]:
    """The experiment kind of a run and why it was put there.

    The sidecar's ``kind`` when it is one of :data:`KINDS`; else (another word is said in
    the reason) the kind whose shape the signals show (:data:`KIND_OF_SHAPE`: held
    position and a two-level u: 'prbs'; no x_ref: 'force_open_loop'; reversing: the
    pre-rolling runs; monotonic with a steady speed: 'constant_speed', else
    'variable_speed'), and a file stem that names a kind must agree with them.  ValueError naming the run
    when neither tells the kind (e.g. a constant signal).
    """
    kind = (run.meta or {}).get("kind")
    where = run_label(run)
    if kind in KINDS:
        return str(kind), "the sidecar's kind"
    found, why = _by_signals(run)
    if kind is not None:
        why = f"the sidecar's kind {kind!r} is not one of {', '.join(KINDS)}; {why}"
    path = getattr(run, "path", None)
    stem = run_stem(path) if path is not None else str((run.meta or {}).get("name", ""))
    named = next((k for k, pattern in _STEMS if re.match(pattern, stem)), None)
    if (
        named is not None
        and found is not None
        and named != found
        and {named, found} != {"constant_speed", "variable_speed"}
    ):
        raise ValueError(
            f"{where}: the file name says {named} but the signals say {found} "
            f"({why}); add a sidecar 'kind' or rename the file"
        )
    if named is not None and found is not None:
        return named, f"file name and signals ({why})"
    if found is None:
        raise ValueError(
            f"{where}: cannot tell which experiment this is: no sidecar 'kind' and "
            f"{why}; add a sidecar 'kind' ({', '.join(KINDS)}) or remove the run"
        )
    return found, f"signals: {why}"


def group_runs(runs: Sequence[Run], why: list[str] | None = None) -> dict[str, list[Run]]:
    """Runs by kind (every key of :data:`KINDS`, possibly empty), in the given order; with
    ``why`` a list, one line per run saying where it went and why is appended to it."""
    out: dict[str, list[Run]] = {k: [] for k in KINDS}
    for r in runs:
        kind, reason = classify_why(r)
        out[kind].append(r)
        if why is not None:
            why.append(f"  {r.name}: {kind} ({reason})")
    return out


def _speed(run: Run) -> float:
    """|cruise speed| [m/s] of a constant-speed run, from its position."""
    Ts = sample_time(run.time, label=run_label(run))
    return abs(steady_segment(np.asarray(run.x, float), Ts, label=run_label(run))[1])


def map_and_stribeck_runs(runs: Sequence[Run]) -> tuple[list[Run], list[Run]]:
    """Split constant-speed runs: those for the maps (every run at the speed of a loaded
    run, loaded or not) and those for the Stribeck curve (every unloaded run)."""
    loads = [run_load_mean(r)[0] for r in runs]
    speeds = [_speed(r) for r in runs]
    loaded = [s for s, P in zip(speeds, loads, strict=True) if abs(P) > LOAD_TOL]
    maps_runs = [
        r
        for r, s in zip(runs, speeds, strict=True)
        if any(abs(s - q) <= SPEED_TOL * q for q in loaded)
    ]
    return maps_runs, [r for r, P in zip(runs, loads, strict=True) if abs(P) <= LOAD_TOL]


@dataclass
class IdentificationResult:
    """Every step's fit, the model file they make, and (with a truth) the comparison."""

    model: ModelFile
    groups: dict[str, list[Run]]
    current_loop: CurrentLoopFit | None = None
    maps: PositionMapsFit | None = None
    stribeck: StribeckFit | None = None
    mass: MassFit | None = None
    attraction: AttractionFit | None = None
    prerolling: PrerollingFit | None = None
    position_friction: PositionFrictionFit | None = None
    #: step -> why it was skipped
    skipped: dict[str, str] = field(default_factory=dict)
    #: FMU parameters that kept the paper's value (not identified)
    defaulted: tuple[str, ...] = ()
    notes: list[str] = field(default_factory=list)
    truth: ModelFile | None = None
    table: list[TruthRow] = field(default_factory=list)
    out_path: Path | None = None
    #: one line per run: the kind it was given and why
    placement: list[str] = field(default_factory=list)

    def text(self) -> str:
        """A plain-text account: runs used, each step's result, the truth table if any."""
        L = [
            f"identification from {sum(len(v) for v in self.groups.values())} runs: "
            + ", ".join(f"{k} {len(v)}" for k, v in self.groups.items())
        ]
        L += self.placement
        p = self.model.parameters
        if self.current_loop is not None:
            c = self.current_loop
            poles = zip(c.pole_hz, c.pole_zeta, strict=True)
            L.append(
                f"current loop: order {c.order}, delay {c.delay}, G(1) = {c.dc_gain:.4f} A/V, "
                f"poles {', '.join(f'{h:.0f} Hz/zeta {z:.2f}' for h, z in poles)}, "
                f"fit {c.fit_percent:.1f} %"
            )
        if self.maps is not None:
            m = self.maps
            L.append(
                f"maps: {len(m.samples.loads)} loads "
                f"{', '.join(f'{P:.4g}' for P in m.samples.loads)} N over "
                f"x = {m.samples.x[0]:.4f} .. {m.samples.x[-1]:.4f} m; fit rms K_f "
                f"{m.ripple.rms_full:.3g} N/A, F_cg {m.cogging.rms_full:.3g} N; periodic-only "
                f"fits +{m.ripple.increase_percent:.0f} % / +{m.cogging.increase_percent:.0f} %"
            )
        if self.stribeck is not None:
            s = self.stribeck
            L.append(
                f"Stribeck: {len(s.points.speed)} speeds {s.points.speed.min() * 1e3:.3g} .. "
                f"{s.points.speed.max() * 1e3:.3g} mm/s, F_s = {p['friction.F_s']:.3f} N, "
                f"F_c = {p['friction.F_c']:.3f} N, V_s = {p['friction.V_s'] * 1e3:.3f} mm/s, "
                f"delta = {p['friction.delta']:.3f}, sigma2 = {p['friction.sigma2']:.2f} N s/m "
                f"(rms residual {s.rms_residual:.3g} N)"
            )
            if s.asymmetry is not None:
                L.append(
                    f"  direction asymmetry (diagnostic, not in the model): dF = "
                    f"{s.asymmetry['asymmetry.dF']:.3f} +- {s.asymmetry['stderr.asymmetry.dF']:.3f} N, "
                    f"dsigma2 = {s.asymmetry['asymmetry.dsigma2']:.2f} +- "
                    f"{s.asymmetry['stderr.asymmetry.dsigma2']:.2f} N s/m"
                )
        if self.mass is not None:
            L.append(
                f"mass: m = {p['m']:.4f} +- {self.mass.stderr['m']:.4f} kg "
                f"({self.mass.n_used} samples, force residual {self.mass.rms_residual:.3g} N)"
            )
        if self.attraction is not None:
            L.append(f"attraction: {self.attraction.message}; model C = {p['friction.C']:.4g} N/s")
        if self.prerolling is not None:
            r = self.prerolling
            L.append(
                f"pre-rolling: N = {len(r.W)}, Delta = "
                + ", ".join(f"{d * 1e6:.1f}" for d in r.Delta)
                + " um, W = "
                + ", ".join(f"{w:.2f}" for w in r.W)
                + f" N; fit rms {100 * r.rms_relative:.2f} % "
                "of F_s"
            )
        if self.position_friction is not None:
            f = self.position_friction
            L.append(
                f"position friction: {f.profile.n} knots over {f.profile.x_start * 1e3:.1f} .. "
                f"{f.profile.x_end * 1e3:.1f} mm, p(x) = {min(f.profile.c) + 1:.3f} .. "
                f"{max(f.profile.c) + 1:.3f} at the knots (median 1; levels x {f.scale:.4f}), "
                f"fit rms {f.rms_residual:.3g} N on {f.n_used} samples"
            )
        for step, why in self.skipped.items():
            L.append(f"SKIPPED {step}: {why}")
        L.extend(self.notes)
        if self.defaulted:
            L.append("kept at the paper's value (not identified): " + _compress(self.defaulted))
        if self.out_path is not None:
            L.append(f"model file: {self.out_path}")
        if self.table:
            L.append("")
            L.append(f"true ({self.truth.name if self.truth else 'truth'}) vs identified:")
            L.append(format_rows(self.table))
        return "\n".join(L)


def _compress(names: Sequence[str]) -> str:
    """'friction.nu[6..10]' style listing of parameter names."""
    out: list[str] = []
    groups: dict[str, list[int]] = {}
    order: list[str] = []
    for n in names:
        m = re.fullmatch(r"(.+)\[(\d+)\]", n)
        if m:
            if m.group(1) not in groups:
                order.append(m.group(1))
                groups[m.group(1)] = []
            groups[m.group(1)].append(int(m.group(2)))
        else:
            order.append(n)
    for n in order:
        if n in groups:
            idx = groups[n]
            out.append(f"{n}[{idx[0]}]" if len(idx) == 1 else f"{n}[{idx[0]}..{idx[-1]}]")
        else:
            out.append(n)
    return ", ".join(out)


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
        + (_compress(res.defaulted) or "none")
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
