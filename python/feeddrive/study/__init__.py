"""Parameter studies: many closed-loop runs of one experiment with varied plant parameters,
serially or on Dask ``distributed`` (a LocalCluster by default, or a scheduler's address).

- :mod:`.schema`: the study file (``feeddrive.study/1``), :func:`load_study`, :class:`StudyError`;
- :mod:`.samplers`: the runs of a design (grid, Latin hypercube, Monte Carlo, one at a time);
- :mod:`.metrics`: reversal, rms and max tracking error, force residual against a measured run;
- :mod:`.run`: one run (a failure is a row), one batch;
- :mod:`.executor`: batches, serial or on a Dask client, rows streamed back, progress bar;
- :mod:`.table`: the results table (CSV as rows arrive, Parquet at the end), resume;
- :mod:`.sensitivity`: one-at-a-time changes or Spearman correlations per parameter and metric;
- :mod:`.sweep`: :func:`run_study`, the whole study;
- :mod:`.bootstrap`: the identification bootstrap on the executor (``identify --bootstrap``);
- :mod:`.bootstrap_study`: the bootstrap as a study file (``"kind": "bootstrap"``),
  :func:`load_study_file` for either kind.
"""

from .bootstrap_study import (
    BootstrapStudy,
    BootstrapStudyResult,
    load_study_file,
    run_bootstrap_study,
    study_reads,
)
from .run import FAILED, OK, RunTask, run_batch, run_case
from .samplers import Case, cases
from .schema import METRICS, SCHEMA, Study, StudyError, load_study, parse_study
from .sensitivity import Sensitivity, sensitivities, sensitivity_text
from .sweep import StudyResult, run_study
from .table import ResultsTable, read_table

__all__ = [
    "FAILED",
    "OK",
    "RunTask",
    "run_batch",
    "run_case",
    "Case",
    "cases",
    "METRICS",
    "SCHEMA",
    "Study",
    "StudyError",
    "load_study",
    "parse_study",
    "Sensitivity",
    "sensitivities",
    "sensitivity_text",
    "StudyResult",
    "run_study",
    "ResultsTable",
    "read_table",
    "BootstrapStudy",
    "BootstrapStudyResult",
    "load_study_file",
    "run_bootstrap_study",
    "study_reads",
]
