"""The identification campaign: every virtual experiment of Secs. 2.2-2.4 on one plant.

Groups (keys of :func:`campaign`) and file stems written by :func:`write_campaign`, one
group per experiment an effect declares (:func:`feeddrive.effects.experiments`: the group,
the run names and the sidecar kinds are written in the effect's module, and its
``campaign`` builder here makes its jobs):

- ``prbs``: ``prbs`` (current loop, Eq. 2);
- ``cogging_ripple``: ``cv_{p|m}20mm_s_P{0,54.9,272.7}`` (Eqs. 4, 5; ``1mm_s`` with ``quick``);
- ``stribeck``: ``cv_{p|m}<v>mm_s_P0`` at 0.3 ... 120 mm/s (Eq. 13; the unloaded pair of
  ``cogging_ripple`` is a Stribeck point too);
- ``force_open_loop``: ``force_open_loop`` (mass);
- ``variable_speed``: ``variable_speed`` (C, Eq. 14);
- ``prerolling``: ``prerolling_A80um``, ``prerolling_A500um`` (Eqs. 15-18).

The full campaign covers the whole stroke at 20 mm/s (six runs of ~16 s of simulated time
each; the paper's 1 mm/s is a Stribeck pair over one magnet pitch); ``quick=True`` shortens
every run (segments of a few mm at 1 mm/s, fewer periods) for tests.
Each job's noise seed is derived from the campaign seed and the job's label.
``repeats=K`` runs every job K times with independent noise (repeat k > 0 seeds from
(seed, label, k), so repeat 0 is the campaign without repeats); the file stems then end in
``_r1`` ... ``_rK``.  Repeats are what the identification bootstrap resamples.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import replace
from functools import partial
from pathlib import Path
from typing import Any, cast

from tqdm import tqdm

from ..data import RECORDING_DECIMALS, Run, write_run
from ..effects import Experiment, experiments, resolve
from ..harness.sensors import Sensors
from ..model_file import ModelFile, load_model, paper_model
from ..outputs import output_dir
from .constant_speed import (
    MAP_SPEED,
    PAPER_LOADS,
    PAPER_SPEED,
    STRIBECK_SPEEDS,
    constant_speed_runs,
    run_seed,
    stribeck_runs,
)
from .force_open_loop import force_open_loop_runs
from .prbs import prbs_runs
from .prerolling_excitation import AMPLITUDES as PREROLLING_AMPLITUDES
from .prerolling_excitation import prerolling_runs
from .variable_speed import variable_speed_runs

#: The groups of the campaign, in the order they are run: the experiments the effects
#: declare (:func:`feeddrive.effects.experiments`).
GROUPS: tuple[str, ...] = tuple(x.group for x in experiments())

Job = tuple[str, str, Callable[[Mapping[str, Any], Sensors], list[Run]]]
#: Most repeats of one campaign (each is a whole campaign of runs).
MAX_REPEATS = 100
#: File formats of the written runs (``--format``): gzip-compressed or plain CSV.
FORMATS: tuple[str, ...] = ("csv.gz", "csv")


def plan(quick: bool = False) -> list[Job]:
    """The campaign's jobs: (group, label, experiment(params, sensors) -> runs), each
    experiment's (:func:`feeddrive.effects.experiments`, in campaign order) from the builder
    it names (:attr:`~feeddrive.effects.Experiment.campaign`).

    One job per run where an experiment has several (so a progress bar counts runs).
    """
    jobs: list[Job] = []
    for x in experiments():
        builder = cast(Callable[[Experiment, bool], list[Job]], resolve(x.campaign))
        jobs += builder(x, quick)
    return jobs


def prbs_jobs(x: Experiment, quick: bool) -> list[Job]:
    """The PRBS run (current loop, Eq. 2)."""
    return [(x.group, x.group, partial(prbs_runs, periods=1 if quick else 4))]


def map_jobs(x: Experiment, quick: bool) -> list[Job]:
    """The constant-speed runs with each of the paper's loads, both directions (Eqs. 4, 5)."""
    jobs: list[Job] = []
    cv_segment = (0.148, 0.152) if quick else None  # None: the whole stroke
    cv_speed = PAPER_SPEED if quick else MAP_SPEED
    for P in PAPER_LOADS:
        for d in (1, -1):
            jobs.append(
                (
                    x.group,
                    f"{x.group}_P{P:g}_d{d:+d}",
                    partial(
                        constant_speed_runs,
                        speeds=(cv_speed,),
                        loads=(P,),
                        directions=(d,),
                        segment=cv_segment,
                    ),
                )
            )
    return jobs


def stribeck_jobs(x: Experiment, quick: bool) -> list[Job]:
    """The unloaded constant-speed runs at each Stribeck speed, both directions (Eq. 13)."""
    speeds = (2e-3, 20e-3) if quick else STRIBECK_SPEEDS
    kw: dict[str, Any] = {"cruise_time": 2.0, "min_length": 4e-3} if quick else {}
    return [
        (
            x.group,
            f"{x.group}_{v * 1e3:g}mm_s_d{d:+d}",
            partial(stribeck_runs, speeds=(v,), directions=(d,), **kw),
        )
        for v in speeds
        for d in (1, -1)
    ]


def force_open_loop_jobs(x: Experiment, quick: bool) -> list[Job]:
    """The open-loop force run (mass, Eq. 1)."""
    return [(x.group, x.group, partial(force_open_loop_runs, n_periods=5 if quick else 10))]


def variable_speed_jobs(x: Experiment, quick: bool) -> list[Job]:
    """The variable-speed run (C, Eq. 14)."""
    return [(x.group, x.group, partial(variable_speed_runs, duration=2.0 if quick else None))]


def prerolling_jobs(x: Experiment, quick: bool) -> list[Job]:
    """One periodic run per amplitude (Eqs. 15-18)."""
    pr: dict[str, Any] = (
        {"period": 2.0, "n_periods": 2.0} if quick else {"period": 4.0, "n_periods": 3.0}
    )
    return [
        (
            x.group,
            f"{x.stem}_A{A * 1e6:g}um",
            partial(prerolling_runs, amplitudes=(A,), **pr),
        )
        for A in PREROLLING_AMPLITUDES
    ]


def _check_repeats(repeats: int) -> int:
    if isinstance(repeats, bool) or not isinstance(repeats, int) or not 1 <= repeats <= MAX_REPEATS:
        raise ValueError(
            f"campaign: repeats must be an integer in [1, {MAX_REPEATS}], got {repeats!r}"
        )
    return repeats


def campaign(
    params: Mapping[str, Any],
    sensors: Sensors,
    quick: bool = False,
    repeats: int = 1,
    progress: bool | None = None,
) -> dict[str, list[Run]]:
    """Run every experiment on the plant ``params`` (FMU parameters, SI).

    Parameters
    ----------
    params : FMU parameters; sensors : noise model and campaign seed; quick : short runs.
    repeats : runs of every job, with independent noise (1 .. :data:`MAX_REPEATS`).
    progress : a bar over the runs on stderr (None: unless ``quick``, on a terminal).

    Returns
    -------
    dict
        Runs by group (:data:`GROUPS`); each run's ``meta['name']`` is its file stem,
        suffixed ``_r1`` ... when ``repeats > 1``, and ``meta['repeat']`` the repeat's number.
    """
    _check_repeats(repeats)
    out: dict[str, list[Run]] = {g: [] for g in GROUPS}
    jobs = [(g, label, fn, k) for g, label, fn in plan(quick) for k in range(repeats)]
    for group, label, fn, k in tqdm(
        jobs,
        desc="experiments",
        unit="run",
        disable=(True if quick else None) if progress is None else not progress,
    ):
        keys = (label,) if k == 0 else (label, k)
        runs = fn(params, replace(sensors, seed=run_seed(sensors.seed, *keys)))
        if repeats > 1:
            for r in runs:
                r.meta["name"] = f"{r.meta['name']}_r{k + 1}"
                r.meta["repeat"] = k + 1
        out[group] += runs
    return out


def _parameters(model: Path | str | ModelFile | Mapping[str, Any] | None) -> dict[str, Any]:
    if model is None:
        return paper_model().fmu_parameters()
    if isinstance(model, ModelFile):
        return model.fmu_parameters()
    if isinstance(model, (str, Path)):
        return load_model(model).fmu_parameters()
    if isinstance(model, Mapping):
        return dict(model)
    raise TypeError(
        f"write_campaign: model must be a path, a ModelFile, a mapping of FMU "
        f"parameters or None, got {type(model).__name__}"
    )


def write_campaign(
    out_dir: Path,
    model: Path | ModelFile | Mapping[str, Any] | None = None,
    seed: int = 1,
    quick: bool = False,
    force: bool = False,
    repeats: int = 1,
    progress: bool | None = None,
    fmt: str = "csv.gz",
) -> list[Path]:
    """Run the campaign on ``model`` (default: the paper's) and write every run.

    Parameters
    ----------
    out_dir : folder for ``<name>.csv.gz`` + ``<name>.json``: checked before the campaign runs,
        written whole at the end (:func:`feeddrive.outputs.output_dir`: it then holds this
        campaign's runs only; a non-empty folder we did not write is refused unless ``force``).
    model : a model file path, a :class:`ModelFile`, FMU parameters, or None (paper).
    seed : campaign seed (sensor noise); quick : short runs (tests).
    repeats : runs of every experiment with independent noise (for ``identify --bootstrap``).
    progress : a bar over the runs on stderr (None: unless ``quick``, on a terminal).
    fmt : ``"csv.gz"`` (gzip-compressed CSV, the default) or ``"csv"`` (:data:`FORMATS`).

    Returns
    -------
    list of Path
        The recordings written, in campaign order.
    """
    params = _parameters(model)
    _check_repeats(repeats)
    if fmt not in FORMATS:
        raise ValueError(f"write_campaign: format must be one of {', '.join(FORMATS)}, got {fmt!r}")
    out_dir = Path(out_dir)
    inputs = (model,) if isinstance(model, (str, Path)) else ()
    with output_dir(out_dir, inputs, force, what="experiments") as stage:
        runs = campaign(
            params, Sensors(seed=int(seed)), quick=quick, repeats=repeats, progress=progress
        )
        names: list[str] = []
        for group in GROUPS:
            for run in runs[group]:
                name = f"{run.meta['name']}.{fmt}"
                if name in names:
                    raise ValueError(f"write_campaign: two runs named {name}")
                write_run(run, stage / name, RECORDING_DECIMALS)
                names.append(name)
    return [out_dir / n for n in names]
