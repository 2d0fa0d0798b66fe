"""Run a study: its cases, the runs not yet in the table, serially or on Dask, the table
written as the runs finish, the sensitivities at the end.

>>> res = run_study(load_study("study.json"), "build/study", workers=2)   # doctest: +SKIP
>>> print(res.summary())                                                 # doctest: +SKIP
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .executor import (
    Progress,
    batches,
    default_batch_size,
    execute_dask,
    execute_serial,
    local_client,
)
from .run import FAILED, RunTask
from .samplers import cases
from .sensitivity import Sensitivity, sensitivities, sensitivity_text
from .spec import Study
from .table import ResultsTable


@dataclass
class StudyResult:
    """A finished (or partly finished) study: its rows in run order and where they are."""

    study: Study
    rows: list[dict[str, Any]]
    csv: Path
    parquet: Path
    n_runs: int
    computed: int  #: runs computed by this call (the others were resumed)
    missing: int  #: runs with no row (lost workers): run again with resume
    wall_s: float
    sensitivities: list[Sensitivity]

    @property
    def failed(self) -> int:
        return sum(r["status"] == FAILED for r in self.rows)

    def summary(self) -> str:
        """Counts, the files and the sensitivity table."""
        head = (
            f"study {self.study.name}: {len(self.rows)}/{self.n_runs} runs in the table "
            f"({self.computed} computed now in {self.wall_s:.1f} s, {self.failed} failed"
            + (f", {self.missing} missing: rerun with --resume" if self.missing else "")
            + f"); wrote {self.csv}, {self.parquet}"
        )
        return head + "\n" + sensitivity_text(self.sensitivities)


def run_study(
    study: Study,
    out: str | Path,
    scheduler: str | None = None,
    workers: int | None = None,
    resume: bool = False,
    progress: bool = False,
    parallel: bool = True,
) -> StudyResult:
    """Run ``study`` into the folder ``out`` (see :mod:`feeddrive.study.table`).

    Parameters
    ----------
    scheduler : address of a Dask scheduler (``tcp://host:8786``); default a LocalCluster.
    workers : LocalCluster worker processes (default one per core).
    resume : keep this study's rows found in ``out`` and compute only the others.
    progress : show a progress bar (runs, failures, ETA).
    parallel : False: every run in this process (no Dask).
    """
    all_cases = cases(study)
    table = ResultsTable(out, study, resume=resume)
    todo = [c for c in all_cases if c.run not in table.done]
    size = study.batch_size or default_batch_size(len(all_cases))
    work = batches(todo, size)
    task = RunTask.of(study)
    bar = Progress(len(all_cases), len(all_cases) - len(todo), progress)

    def sink(rows: list[dict[str, Any]]) -> None:
        table.add(rows)
        bar.update(rows)

    t0 = time.perf_counter()
    try:
        if not parallel or not work:
            missing = execute_serial(task, work, sink)
        else:
            with local_client(scheduler, workers) as client:
                missing = execute_dask(task, work, sink, client)
    finally:
        bar.close()
        csv_path, pq_path = table.close()
    rows = table.sorted_rows()
    return StudyResult(
        study=study,
        rows=rows,
        csv=csv_path,
        parquet=pq_path,
        n_runs=len(all_cases),
        computed=len(todo) - missing,
        missing=missing,
        wall_s=time.perf_counter() - t0,
        sensitivities=sensitivities(study, rows),
    )
