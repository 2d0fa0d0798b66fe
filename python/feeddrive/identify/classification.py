"""Which experiment each run is: the sidecar's ``kind``, else the file stem, else the
signals (the kinds are those of the experiments the effects declare,
:func:`feeddrive.effects.run_kinds`); the runs grouped by kind, and the constant-speed runs
split between the maps and the Stribeck curve."""

from __future__ import annotations

import re
from collections.abc import Sequence

import numpy as np

from ..data import Run, run_stem
from ..effects import run_kinds
from ..physics import run_load_mean
from ..signals import run_label, sample_time
from ._signals import steady_segment

#: Experiment kinds (the sidecar's ``kind``) and what each is used for: the kinds of the
#: experiments the effects declare (:func:`feeddrive.effects.run_kinds`), in campaign order.
KINDS: dict[str, str] = {k.kind: k.uses for k in run_kinds().values()}
#: The file stems (regular expressions at the stem's start) that name each kind.
_STEMS = tuple((k.kind, k.file_pattern) for k in run_kinds().values())
#: The kind whose runs' signals show each shape (:data:`feeddrive.effects.SHAPES`).
KIND_OF_SHAPE: dict[str, str] = {k.shape: k.kind for k in run_kinds().values()}
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
