"""The identification bootstrap as a study: replicates of
:mod:`feeddrive.identify.bootstrap` in batches on the study executor (serial, a Dask
LocalCluster, or a scheduler's address), intervals written into the identified model file.

>>> res, boot = bootstrap_folder("build/runs", "build/identified.json", 200, workers=2)  # doctest: +SKIP
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

from ..data import Run
from ..harness.checked_runs import load_checked_runs
from ..identify import parametric
from ..identify.bootstrap import (
    Bootstrap,
    BootstrapTask,
    check_campaign,
    identified_names,
    intervals,
    run_replicates,
    single_run_parameters,
)
from ..identify.pipeline import identify_runs
from ..identify.result import IdentificationResult
from ..model_file import ModelFile, save_model
from .executor import (
    Progress,
    batches,
    default_batch_size,
    execute_dask,
    execute_serial,
    local_client,
)

#: The interval methods of ``identify --bootstrap`` (``--interval-method``).
METHODS = (parametric.METHOD, "runs")


def check_arguments(n: int, level: float, workers: int | None, seed: int) -> None:
    """ValueError naming the argument and its rule."""
    if isinstance(n, bool) or not isinstance(n, int) or n < 2:
        raise ValueError(f"--bootstrap {n!r}: must be an integer >= 2 (replicates)")
    if not 0 < level < 1:
        raise ValueError(f"--level {level!r}: must be in (0, 1)")
    if workers is not None and workers < 1:
        raise ValueError(f"--workers {workers}: must be >= 1")
    if seed < 0:
        raise ValueError(f"--seed {seed}: must be >= 0")


def check_parametric_replicates(n: int) -> None:
    """ValueError when ``n`` is too few replicates for a parametric interval."""
    if n < parametric.MIN_REPLICATES:
        raise ValueError(
            f"--bootstrap {n}: the parametric intervals need at least "
            f"{parametric.MIN_REPLICATES} replicates (their spread and bias are "
            "estimated from them)"
        )


def run_bootstrap(
    runs: Sequence[Run],
    model: ModelFile,
    defaulted: Sequence[str],
    n: int,
    seed: int = 0,
    level: float = 0.95,
    scheduler: str | None = None,
    workers: int | None = None,
    parallel: bool = True,
    progress: bool = False,
    options: Mapping[str, Any] | None = None,
) -> Bootstrap:
    """``n`` replicates of the identification of ``runs`` and the intervals of every
    parameter of ``model`` the pipeline identified (not in ``defaulted``).

    Parameters
    ----------
    runs : the campaign (whole runs are resampled within cells of repeats).
    seed : replicate r resamples with ``default_rng([seed, r])``.
    level : the intervals' coverage (percentiles (1 -+ level)/2).
    scheduler, workers, parallel : as :func:`feeddrive.study.run_study`.
    options : keywords of :func:`~feeddrive.identify.pipeline.identify_runs` (no ``truth``).
    """
    check_arguments(n, level, workers, seed)
    groups = check_campaign(runs)
    names = identified_names(model, defaulted)
    task = BootstrapTask(
        runs=tuple(runs),
        cells=tuple(tuple(g) for g in groups),
        names=names,
        seed=int(seed),
        options=tuple(sorted((options or {}).items())),
    )
    t0 = time.perf_counter()
    rows, n_workers = _execute(task, n, run_replicates, scheduler, workers, parallel, progress)
    single = [runs[g[0]].name for g in groups if len(g) == 1]
    refused = single_run_parameters(rows, names, max(len(g) for g in groups))
    ok = [r for r in rows if r["status"] == "ok"]
    fixed = [k for k in names if ok and len({r[k] for r in ok}) == 1]
    uncertainty = {
        k: {**v, "method": "runs"}
        for k, v in intervals(rows, names, level).items()
        if k not in refused and k not in fixed
    }
    return Bootstrap(
        rows=rows,
        uncertainty=uncertainty,
        n_cells=len(groups),
        single=single,
        wall_s=time.perf_counter() - t0,
        workers=n_workers,
        refused=refused,
        fixed=fixed,
    )


def _execute(
    task: Any,
    n: int,
    fn: Any,
    scheduler: str | None,
    workers: int | None,
    parallel: bool,
    progress: bool,
) -> tuple[list[dict[str, Any]], int]:
    """Replicates 0..n-1 of ``task`` by ``fn`` on the executor: rows in replicate order and
    the number of workers."""
    work = batches(list(range(n)), default_batch_size(n))
    rows: list[dict[str, Any]] = []
    bar = Progress(n, 0, progress)

    def sink(batch_rows: list[dict[str, Any]]) -> None:
        rows.extend(batch_rows)
        bar.update(batch_rows)

    n_workers = 1
    try:
        if not parallel:
            execute_serial(task, work, sink, fn=fn)
        else:
            with local_client(scheduler, workers) as client:
                n_workers = len(client.scheduler_info()["workers"])
                missing = execute_dask(task, work, sink, client, fn=fn)
            if missing:
                raise RuntimeError(
                    f"identify --bootstrap: {missing} replicates lost with their workers"
                )
    finally:
        bar.close()
    rows.sort(key=lambda r: r["replicate"])
    return rows, n_workers


def run_parametric(
    runs: Sequence[Run],
    fit: IdentificationResult,
    n: int,
    seed: int = 0,
    level: float = 0.95,
    scheduler: str | None = None,
    workers: int | None = None,
    parallel: bool = True,
    progress: bool = False,
    options: Mapping[str, Any] | None = None,
) -> Bootstrap:
    """``n`` parametric replicates (:mod:`feeddrive.identify.parametric`): every run of
    ``runs`` simulated again on ``fit.model`` with the measured noise, identified again;
    bias-corrected intervals of every identified parameter, the refusals with their reason.

    Parameters as :func:`run_bootstrap`; ``fit`` is the identification of ``runs``.
    ValueError when a run cannot be simulated again (its sidecar lacks the controller, ...).
    """
    check_arguments(n, level, workers, seed)
    check_parametric_replicates(n)
    why = parametric.why_not_resimulable(runs)
    if why is not None:
        raise ValueError(f"identify --bootstrap: {why}")
    sensors, noise_text = parametric.measured_sensors(runs, fit)
    names = identified_names(fit.model, fit.defaulted)
    task = parametric.ParametricTask(
        runs=tuple(runs),
        params=tuple(fit.model.fmu_parameters().items()),
        sensors=sensors,
        names=names,
        seed=int(seed),
        options=tuple(sorted((options or {}).items())),
        current_only=parametric.current_only(runs),
    )
    t0 = time.perf_counter()
    rows, n_workers = _execute(
        task, n, parametric.run_replicates, scheduler, workers, parallel, progress
    )
    structure = (
        f"{fit.current_loop.order}/{fit.current_loop.delay}" if fit.current_loop is not None else ""
    )
    iv = parametric.bias_corrected(fit.model.parameters, rows, names, level, structure)
    return Bootstrap(
        rows=rows,
        uncertainty=iv.uncertainty,
        n_cells=len(runs),
        wall_s=time.perf_counter() - t0,
        workers=n_workers,
        method=parametric.METHOD,
        refused=iv.refused,
        noise=noise_text,
        evidence=iv.evidence,
        fixed=iv.fixed,
    )


def bootstrap_folder(
    runs_dir: str | Path,
    out: str | Path | None,
    n: int,
    seed: int = 0,
    level: float = 0.95,
    truth: Any = None,
    scheduler: str | None = None,
    workers: int | None = None,
    parallel: bool = True,
    progress: bool = False,
    method: str = parametric.METHOD,
) -> tuple[IdentificationResult, Bootstrap]:
    """``feeddrive identify DIR --bootstrap N``: identify the folder, bootstrap it, write the
    model file with its ``uncertainty`` (arguments and ``out`` checked before any work).

    ``method``: 'parametric' (default: :func:`run_parametric`, bias-corrected intervals from
    simulated campaigns) or 'runs' (:func:`run_bootstrap`, percentiles over whole runs
    resampled within cells of repeats: the noise spread only, no bias)."""
    check_arguments(n, level, workers, seed)
    if method not in METHODS:
        raise ValueError(f"--interval-method {method!r}: must be one of {', '.join(METHODS)}")
    inputs = (truth,) if isinstance(truth, (str, Path)) else ()
    side_notes: list[str] = []
    runs = load_checked_runs(runs_dir, out, truth, side_notes)
    why = None
    if method == "runs":
        check_campaign(runs)
    else:
        check_parametric_replicates(n)
        why = parametric.why_not_resimulable(runs)
    res = identify_runs(runs, truth=truth)
    res.notes[:0] = side_notes
    if method == "runs":
        boot = run_bootstrap(
            runs,
            res.model,
            res.defaulted,
            n,
            seed=seed,
            level=level,
            scheduler=scheduler,
            workers=workers,
            parallel=parallel,
            progress=progress,
        )
    elif why is not None:  # the sidecars do not say how to repeat a run: no intervals
        boot = Bootstrap(
            rows=[],
            uncertainty={},
            n_cells=len(runs),
            method=parametric.METHOD,
            refused={"every parameter": why},
        )
    else:
        boot = run_parametric(
            runs,
            res,
            n,
            seed=seed,
            level=level,
            scheduler=scheduler,
            workers=workers,
            parallel=parallel,
            progress=progress,
        )
    res.notes += [f"no interval for {k}: {why}" for k, why in boot.refused.items()]
    res.model = replace(res.model, uncertainty=boot.uncertainty)
    if out is not None:
        save_model(res.model, out, inputs)
        res.out_path = Path(out)
    return res, boot
