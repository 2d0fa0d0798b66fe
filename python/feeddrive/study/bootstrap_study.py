"""The identification bootstrap as a study file: ``feeddrive sweep BOOT.json --out DIR``.

Format (schema ``feeddrive.study/1``, ``kind`` ``bootstrap``)::

    {"schema": "feeddrive.study/1", "kind": "bootstrap", "name": "campaign intervals",
     "runs": "campaign/",          # folder of recordings with repeats (relative to this file)
     "replicates": 200,            # >= 2
     "level": 0.95,                # optional, in (0, 1)
     "seed": 0,                    # optional, >= 0
     "method": "parametric",       # optional: "parametric" (default) or "runs"
     "truth": "truth.json"}        # optional: a model file to compare with (virtual runs)

It runs :func:`feeddrive.study.bootstrap.bootstrap_folder` on the study executor (serial,
LocalCluster, scheduler) and writes into DIR: ``model.json`` (the identified model with its
``uncertainty``), ``replicates.csv`` / ``replicates.parquet`` (one row per replicate: every
identified parameter, ``wall_s``, ``status``, ``message``) and the report.  The whole folder is
written at the end (:func:`feeddrive.outputs.output_dir`): an interrupted bootstrap leaves the
previous results in place; a replicate depends on (seed, r) only, so a rerun gives the same
table.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

from ..identify.bootstrap import Bootstrap
from ..identify.result import IdentificationResult
from ..model_file import load_model
from ..outputs import Reads, output_dir
from .bootstrap import METHODS, bootstrap_folder
from .fields import StudyError
from .schema import KINDS, SCHEMA, parse_study, read_study_json
from .spec import Study

KIND = "bootstrap"
_KEYS = (
    "schema",
    "kind",
    "name",
    "description",
    "runs",
    "replicates",
    "level",
    "seed",
    "truth",
    "method",
)
MODEL_NAME, CSV_NAME, PARQUET_NAME = "model.json", "replicates.csv", "replicates.parquet"


@dataclass(frozen=True)
class BootstrapStudy:
    """A validated bootstrap study file (paths resolved against the file's folder)."""

    source: str
    name: str
    runs: Path
    replicates: int
    level: float = 0.95
    seed: int = 0
    truth: Path | None = None
    method: str = "parametric"


def _int(raw: dict[str, Any], key: str, src: str, low: int, default: int | None = None) -> int:
    v = raw.get(key, default)
    if isinstance(v, bool) or not isinstance(v, int) or v < low:
        raise StudyError(src, key, f"must be an integer >= {low}, got {v!r}")
    return v


def parse_bootstrap_study(raw: dict[str, Any], src: str, base: Path) -> BootstrapStudy:
    """Check a bootstrap study's JSON object; :class:`StudyError` names the field."""
    for k in raw:
        if k not in _KEYS:
            raise StudyError(
                src, k, f"unknown key for kind 'bootstrap' (known: {', '.join(_KEYS)})"
            )
    if raw.get("schema") != SCHEMA:
        raise StudyError(src, "schema", f"must be {SCHEMA!r}, got {raw.get('schema')!r}")
    runs = raw.get("runs")
    if not isinstance(runs, str) or not runs:
        raise StudyError(src, "runs", f"must be the path of a folder of runs, got {runs!r}")
    runs_dir = (base / runs).resolve()
    if not runs_dir.is_dir():
        raise StudyError(src, "runs", f"{runs_dir} is not a folder")
    level = raw.get("level", 0.95)
    if isinstance(level, bool) or not isinstance(level, (int, float)) or not 0 < level < 1:
        raise StudyError(src, "level", f"must be a number in (0, 1), got {level!r}")
    truth = raw.get("truth")
    if truth is not None and (not isinstance(truth, str) or not (base / truth).is_file()):
        raise StudyError(src, "truth", f"must be the path of a model file, got {truth!r}")
    method = raw.get("method", "parametric")
    if method not in METHODS:
        raise StudyError(src, "method", f"must be one of {', '.join(METHODS)}, got {method!r}")
    name = raw.get("name", Path(src).stem)
    if not isinstance(name, str):
        raise StudyError(src, "name", f"must be a string, got {name!r}")
    return BootstrapStudy(
        source=src,
        name=name,
        runs=runs_dir,
        replicates=_int(raw, "replicates", src, 2),
        level=float(level),
        seed=_int(raw, "seed", src, 0, 0),
        method=method,
        truth=(base / truth).resolve() if truth is not None else None,
    )


def study_reads(path: str | Path) -> Reads:
    """Every file a study file makes a sweep read: the study file, its ``model`` or ``truth``
    file, its ``experiment.measured`` run (and sidecar), its ``runs`` folder (each run and
    sidecar).  A file that cannot be read as a study names the study file only (loading it
    then reports the problem)."""
    path = Path(path)
    try:
        raw = read_study_json(path)
    except (StudyError, OSError):
        raw = None
    if not isinstance(raw, dict):
        return Reads.of(files=[path])

    def rel(value: Any) -> Path | None:
        return path.parent / value if isinstance(value, str) and value else None

    exp = raw.get("experiment")
    return Reads.of(
        files=[path, rel(raw.get("model")), rel(raw.get("truth"))],
        runs=[rel(exp.get("measured")) if isinstance(exp, dict) else None],
        run_folders=[rel(raw.get("runs"))],
    )


def load_study_file(path: str | Path) -> Study | BootstrapStudy:
    """Any study file: a parameter sweep (:class:`Study`) or, with ``"kind": "bootstrap"``,
    a :class:`BootstrapStudy`; :class:`StudyError` names the file and the field."""
    path = Path(path)
    raw = read_study_json(path)
    kind = raw.get("kind", "sweep") if isinstance(raw, dict) else "sweep"
    if kind not in KINDS:
        raise StudyError(str(path), "kind", f"must be one of {', '.join(KINDS)}, got {kind!r}")
    if kind == KIND:
        return parse_bootstrap_study(raw, str(path), path.parent)
    return parse_study(raw, str(path), path.parent)


@dataclass
class BootstrapStudyResult:
    """A finished bootstrap study: the identification, the replicates, the files."""

    study: BootstrapStudy
    identification: IdentificationResult
    bootstrap: Bootstrap
    out: Path

    def summary(self) -> str:
        """Counts and cost, then one line per interval."""
        lines = [
            f"study {self.study.name}, " + self.bootstrap.text(),
            f"{'parameter':24s} {'value':>14s} {'lo':>14s} {'hi':>14s}",
        ]
        model = self.identification.model
        for name, iv in model.uncertainty.items():
            lines.append(
                f"{name:24s} {model.parameters[name]:14.6g} {iv['lo']:14.6g} {iv['hi']:14.6g}"
            )
        lines.append(
            f"wrote {self.out / MODEL_NAME}, {self.out / CSV_NAME}, {self.out / PARQUET_NAME}"
        )
        return "\n".join(lines)


def _write_rows(rows: list[dict[str, Any]], folder: Path) -> None:
    cols: list[str] = []
    for r in rows:
        cols += [c for c in r if c not in cols]
    with open(folder / CSV_NAME, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow([repr(r[c]) if isinstance(r.get(c), float) else r.get(c, "") for c in cols])

    def column(c: str) -> pa.Array:
        vals = [r.get(c) for r in rows]
        if all(
            (isinstance(v, (int, float)) and not isinstance(v, bool)) or v is None for v in vals
        ) and c not in ("status", "message"):
            return (
                pa.array([math.nan if v is None else float(v) for v in vals], pa.float64())
                if c != "replicate"
                else pa.array(vals, pa.int64())
            )
        return pa.array(["" if v is None else str(v) for v in vals], pa.string())

    pq.write_table(pa.table({c: column(c) for c in cols}), folder / PARQUET_NAME)


def run_bootstrap_study(
    study: BootstrapStudy,
    out: str | Path,
    scheduler: str | None = None,
    workers: int | None = None,
    parallel: bool = True,
    progress: bool = False,
    force: bool = False,
) -> BootstrapStudyResult:
    """Run ``study`` into the folder ``out`` (checked first; written whole at the end; a
    non-empty folder feeddrive did not write is refused unless ``force``)."""
    out = Path(out)
    inputs = [study.runs, Path(study.source)] + ([study.truth] if study.truth else [])
    with output_dir(out, inputs, force=force, what="bootstrap study") as stage:
        res, boot = bootstrap_folder(
            study.runs,
            stage / MODEL_NAME,
            study.replicates,
            seed=study.seed,
            level=study.level,
            truth=load_model(study.truth).fmu_parameters() if study.truth else None,
            scheduler=scheduler,
            workers=workers,
            parallel=parallel,
            progress=progress,
            method=study.method,
        )
        _write_rows(boot.rows, stage)
        (stage / "study.json").write_text(
            json.dumps(
                {
                    "kind": KIND,
                    "source": study.source,
                    "runs": str(study.runs),
                    "replicates": study.replicates,
                    "level": study.level,
                    "seed": study.seed,
                    "method": study.method,
                },
                indent=1,
            )
            + "\n",
            encoding="utf-8",
        )
    res.out_path = out / MODEL_NAME
    return BootstrapStudyResult(study=study, identification=res, bootstrap=boot, out=out)
