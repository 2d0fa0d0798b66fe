"""The results table of a study: one row per run, written as the runs finish.

Columns: ``run`` (id), ``label`` (oat: which end of which parameter), the varied parameters,
the metrics, ``wall_s``, ``status`` (``ok`` / ``failed``) and ``message``.  Files in the
output folder:

- ``results.csv``: rows appended (and flushed) as they arrive, floats with ``repr`` (the CSV
  gives back the same float64 bits); rewritten in run order when the study ends;
- ``results.parquet`` (pyarrow), written when the study ends;
- ``study.json``: the study's identity (its canonical JSON and the base model's parameters);
  a folder holding another study's results is refused, and this study's finished rows are
  kept and skipped on ``resume``.
"""

from __future__ import annotations

import csv
import hashlib
import json
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

from ..model_file import INTEGER_PARAMETERS
from .spec import Study

CSV_NAME, PARQUET_NAME, IDENTITY_NAME = "results.csv", "results.parquet", "study.json"


def study_identity(study: Study) -> dict[str, Any]:
    """What makes two studies the same: the study file's content and the base model."""
    doc = {"study": json.loads(study.text), "model": study.model.fmu_parameters()}
    digest = hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()
    return {"sha256": digest, **doc}


def _fmt(v: Any) -> str:
    return repr(v) if isinstance(v, float) else str(v)


class ResultsTable:
    """The study's rows: those found in ``out`` (resume) and those added since."""

    def __init__(self, out: str | Path, study: Study, resume: bool = False) -> None:
        self.out = Path(out)
        self.columns = (
            ["run", "label"]
            + list(study.parameter_names)
            + list(study.metric_columns)
            + ["wall_s", "status", "message"]
        )
        self._types: dict[str, type] = dict.fromkeys(self.columns, float)
        self._types.update({"run": int, "label": str, "status": str, "message": str})
        self._types.update({n: int for n in study.parameter_names if n in INTEGER_PARAMETERS})
        self.rows: dict[int, dict[str, Any]] = {}
        ident = study_identity(study)
        id_path = self.out / IDENTITY_NAME
        csv_path = self.out / CSV_NAME
        if id_path.exists() or csv_path.exists():
            try:
                old = json.loads(id_path.read_text(encoding="utf-8")).get("sha256")
            except (OSError, ValueError, AttributeError):
                old = None
            if old != ident["sha256"]:
                raise ValueError(
                    f"{self.out}: holds the results of another study (its "
                    f"{IDENTITY_NAME} differs); give another --out, or --force to replace them"
                )
            if not resume:
                raise ValueError(
                    f"{self.out}: already holds results of this study; give "
                    f"--resume to compute only the missing runs, --force to start again, or another --out"
                )
            self.rows = self._read(csv_path) if csv_path.exists() else {}
        self.out.mkdir(parents=True, exist_ok=True)
        id_path.write_text(json.dumps(ident, indent=1, sort_keys=True) + "\n", encoding="utf-8")
        self._rewrite_csv()  # drops a partial last line of an interrupted study
        # held open for the rows to come; close() closes it
        self._file = open(csv_path, "a", newline="", encoding="utf-8")  # noqa: SIM115
        self._writer = csv.writer(self._file)

    def _read(self, path: Path) -> dict[int, dict[str, Any]]:
        rows: dict[int, dict[str, Any]] = {}
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            if reader.fieldnames != self.columns:
                raise ValueError(
                    f"{path}: columns {reader.fieldnames} are not this study's {self.columns}"
                )
            for raw in reader:
                try:
                    row = {c: self._types[c](raw[c]) for c in self.columns}
                except (TypeError, ValueError):
                    continue  # an interrupted write: the run is computed again
                rows[row["run"]] = row
        return rows

    @property
    def done(self) -> set[int]:
        """Ids of the runs that have a row (finished, ok or failed)."""
        return set(self.rows)

    def add(self, rows: Iterable[dict[str, Any]]) -> None:
        """Append rows (written and flushed at once)."""
        for row in rows:
            self.rows[int(row["run"])] = row
            self._writer.writerow([_fmt(row[c]) for c in self.columns])
        self._file.flush()

    def sorted_rows(self) -> list[dict[str, Any]]:
        return [self.rows[k] for k in sorted(self.rows)]

    def _rewrite_csv(self) -> None:
        path = self.out / CSV_NAME
        tmp = path.with_suffix(".csv.tmp")
        with open(tmp, "w", newline="", encoding="utf-8") as f:
            w = csv.writer(f)
            w.writerow(self.columns)
            for row in self.sorted_rows():
                w.writerow([_fmt(row[c]) for c in self.columns])
        os.replace(tmp, path)

    def arrow(self) -> pa.Table:
        """The rows in run order as a pyarrow Table (typed columns)."""
        kinds = {float: pa.float64(), int: pa.int64(), str: pa.string()}
        rows = self.sorted_rows()
        return pa.table(
            {c: pa.array([r[c] for r in rows], type=kinds[self._types[c]]) for c in self.columns}
        )

    def close(self) -> tuple[Path, Path]:
        """Rewrite the CSV in run order, write the Parquet file; their paths."""
        self._file.close()
        self._rewrite_csv()
        pq.write_table(self.arrow(), self.out / PARQUET_NAME)
        return self.out / CSV_NAME, self.out / PARQUET_NAME


def read_table(path: str | Path) -> list[dict[str, Any]]:
    """Rows of a study's ``results.parquet`` (as dicts, run order)."""
    t = pq.read_table(path)
    return t.to_pylist()
