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
from ..identify.bootstrap import (Bootstrap, BootstrapTask, check_campaign, identified_names,
                                  intervals, run_replicates)
from ..identify.pipeline import IdentificationResult, identify_runs, load_checked_runs
from ..model_file import ModelFile, save_model
from .executor import Progress, batches, default_batch_size, execute_dask, execute_serial, local_client


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


def run_bootstrap(runs: Sequence[Run], model: ModelFile, defaulted: Sequence[str], n: int,
                  seed: int = 0, level: float = 0.95, scheduler: str | None = None,
                  workers: int | None = None, parallel: bool = True, progress: bool = False,
                  options: Mapping[str, Any] | None = None) -> Bootstrap:
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
    task = BootstrapTask(runs=tuple(runs), cells=tuple(tuple(g) for g in groups), names=names,
                         seed=int(seed), options=tuple(sorted((options or {}).items())))
    work = batches(list(range(n)), default_batch_size(n))
    rows: list[dict[str, Any]] = []
    bar = Progress(n, 0, progress)

    def sink(batch_rows: list[dict[str, Any]]) -> None:
        rows.extend(batch_rows)
        bar.update(batch_rows)

    t0 = time.perf_counter()
    n_workers = 1
    try:
        if not parallel:
            execute_serial(task, work, sink, fn=run_replicates)
        else:
            with local_client(scheduler, workers) as client:
                n_workers = len(client.scheduler_info()["workers"])
                missing = execute_dask(task, work, sink, client, fn=run_replicates)
            if missing:
                raise RuntimeError(f"identify --bootstrap: {missing} replicates lost with "
                                   "their workers")
    finally:
        bar.close()
    rows.sort(key=lambda r: r["replicate"])
    single = [runs[g[0]].name for g in groups if len(g) == 1]
    return Bootstrap(rows=rows, uncertainty=intervals(rows, names, level), n_cells=len(groups),
                     single=single, wall_s=time.perf_counter() - t0, workers=n_workers)


def bootstrap_folder(runs_dir: str | Path, out: str | Path | None, n: int, seed: int = 0,
                     level: float = 0.95, truth: Any = None, scheduler: str | None = None,
                     workers: int | None = None, parallel: bool = True,
                     progress: bool = False) -> tuple[IdentificationResult, Bootstrap]:
    """``feeddrive identify DIR --bootstrap N``: identify the folder, bootstrap it, write the
    model file with its ``uncertainty`` (arguments and ``out`` checked before any work)."""
    check_arguments(n, level, workers, seed)
    inputs = (truth,) if isinstance(truth, (str, Path)) else ()
    side_notes: list[str] = []
    runs = load_checked_runs(runs_dir, out, truth, side_notes)
    check_campaign(runs)
    res = identify_runs(runs, truth=truth)
    res.notes[:0] = side_notes
    boot = run_bootstrap(runs, res.model, res.defaulted, n, seed=seed, level=level,
                         scheduler=scheduler, workers=workers, parallel=parallel,
                         progress=progress)
    res.model = replace(res.model, uncertainty=boot.uncertainty)
    if out is not None:
        save_model(res.model, out, inputs)
        res.out_path = Path(out)
    return res, boot
