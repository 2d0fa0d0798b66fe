"""Run a study's cases in batches, serially or on Dask ``distributed``, rows streamed back.

- :func:`batches`: consecutive cases in batches (default :func:`default_batch_size`, a
  function of the number of runs only, so serial and parallel runs batch alike);
- :func:`execute_serial`: every batch in this process;
- :func:`execute_dask`: every batch a task on a Dask client; the study's
  :class:`~feeddrive.study.run.RunTask` is scattered once to every worker, results are
  handed over as they complete (``distributed.as_completed``);
- :func:`local_client`: a ``LocalCluster`` with one worker process per core
  (``threads_per_worker=1``), or a client of an existing scheduler (``tcp://host:port``).

A batch whose worker was lost (killed twice over) leaves its runs missing: they are
computed by the next ``--resume``.  Progress: tqdm (runs done, failures, ETA).
"""

from __future__ import annotations

import logging
import math
import os
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any, TypeVar

from distributed import Client, LocalCluster, as_completed
from tqdm import tqdm

from .run import FAILED, run_batch

T = TypeVar("T")

RowsSink = Callable[[list[dict[str, Any]]], None]
#: One executor task: (the scattered task, a batch) -> rows (a study's run_batch, a bootstrap's).
BatchFn = Callable[[Any, Sequence[Any]], list[dict[str, Any]]]


def default_batch_size(n_runs: int) -> int:
    """Runs per task: about 32 tasks per study (16 per worker on 2 cores: the scheduler's
    share stays a few per cent of 0.2 s runs), at most 64 runs per task."""
    return max(1, min(64, math.ceil(n_runs / 32)))


def batches(cases: Sequence[T], size: int) -> list[list[T]]:
    """``cases`` in consecutive batches of ``size``."""
    return [list(cases[k : k + size]) for k in range(0, len(cases), size)]


class Progress:
    """A tqdm bar over runs with the count of failed runs."""

    def __init__(self, total: int, initial: int, enabled: bool) -> None:
        self.failed = 0
        self.bar = tqdm(
            total=total, initial=initial, unit="run", disable=not enabled, dynamic_ncols=True
        )

    def update(self, rows: list[dict[str, Any]]) -> None:
        self.failed += sum(r["status"] == FAILED for r in rows)
        self.bar.set_postfix(failed=self.failed, refresh=False)
        self.bar.update(len(rows))

    def close(self) -> None:
        self.bar.close()


def execute_serial(
    task: Any, work: Sequence[list[Any]], sink: RowsSink, fn: BatchFn = run_batch
) -> int:
    """Run every batch here (``fn(task, batch)``, default a study's :func:`run_batch`);
    returns the number of runs left missing (0)."""
    for b in work:
        sink(fn(task, b))
    return 0


def execute_dask(
    task: Any, work: Sequence[list[Any]], sink: RowsSink, client: Client, fn: BatchFn = run_batch
) -> int:
    """Run every batch as a task ``fn(task, batch)`` on ``client`` (default a study's
    :func:`run_batch`); returns the runs left missing (lost workers)."""
    if not work:
        return 0
    [shared] = client.scatter([task], broadcast=True)
    futures = [client.submit(fn, shared, b, pure=False) for b in work]
    size = {f.key: len(b) for f, b in zip(futures, work, strict=True)}
    missing = 0
    for fut in as_completed(futures):
        try:
            rows = fut.result()
        except Exception:  # a lost worker (KilledWorker) or a broken batch: not rows
            missing += size[fut.key]
            continue
        finally:
            fut.release()
        sink(rows)
    return missing


@contextmanager
def local_client(scheduler: str | None = None, workers: int | None = None) -> Iterator[Client]:
    """A Dask client: of ``scheduler`` when given, else of a LocalCluster of ``workers``
    processes (default one per core), one thread each."""
    if scheduler is not None:
        with Client(scheduler) as client:
            yield client
        return
    n = workers or os.cpu_count() or 1
    with (
        LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=logging.ERROR,
        ) as cluster,
        Client(cluster) as client,
    ):
        yield client
