"""The parsers of the commands on recorded data (plan, identify, diagnose, sweep): each
command's arguments, help and example, and the call of its work."""

from __future__ import annotations

import argparse
from pathlib import Path

from .arguments import (
    BLOCKS,
    FILE,
    FINITE,
    INTERVAL_METHODS,
    LEVEL,
    OUT_DIR,
    OUT_FILE,
    POSITIVE,
    REPLICATES,
    RUN,
    RUNS,
    SEED,
    STEPS,
    STUDY,
    WINDOW,
    command,
    force_argument,
    path_argument,
    progress_argument,
)

# each command's work (feeddrive.commands.<name>) is imported only when the command runs


def _cmd_plan(a: argparse.Namespace) -> int:
    from ..commands import plan

    return plan.main(a)


def _loads(text: str) -> tuple[float, ...]:
    """``--loads``: comma-separated finite loads [N]."""
    try:
        values = tuple(float(t) for t in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a comma-separated list of numbers [N]"
        ) from None
    if not all(abs(v) < float("inf") for v in values):
        raise argparse.ArgumentTypeError(f"{text} is out of range: loads must be finite [N]")
    return tuple(v for v in values if v != 0)


def register_plan(sub) -> None:
    p = command(
        sub,
        "plan",
        "the identification campaign as references and sidecars to run on "
        "a real drive, sized to its limits",
        reads="--model: the nominal model file (default: the paper's model);\n"
        "--controller: the drive's controller as a JSON spec (docs/data-format.md)",
        writes="OUT/plan.md (and plan.html with --html): the runs in order, what to record\n"
        "and why; OUT/reference/NN_name.csv (time,x_ref or time,u);\n"
        "OUT/sidecar/NN_name.json (keep it beside the recording)",
        example="feeddrive plan --out myplan --stroke 0.05 0.45 --v-max 0.2 --loads 50,250",
    )
    path_argument(p, OUT_DIR, "--out", required=True, help="output folder of the plan")
    path_argument(
        p, FILE, "--model", default=None, help="nominal model file (default: the paper's)"
    )
    path_argument(
        p,
        FILE,
        "--controller",
        default=None,
        help="the drive's controller as a JSON spec for the sidecars (default: a PID with lead)",
    )
    p.add_argument(
        "--stroke",
        type=FINITE,
        nargs=2,
        metavar=("X0", "X1"),
        default=None,
        help="usable stroke [m] (default: the model's)",
    )
    p.add_argument("--v-max", type=POSITIVE, default=None, help="speed limit [m/s] (default 0.25)")
    p.add_argument(
        "--a-max", type=POSITIVE, default=None, help="acceleration limit [m/s^2] (default 5)"
    )
    p.add_argument(
        "--u-limit",
        type=POSITIVE,
        default=None,
        help="amplifier reference range +- [V] (default 10)",
    )
    p.add_argument(
        "--loads",
        type=_loads,
        default=None,
        metavar="N,...",
        help="loads to hang for the maps [N] (default 54.9,272.7)",
    )
    p.add_argument("--html", action="store_true", help="also write plan.html")
    force_argument(p)
    p.set_defaults(func=_cmd_plan)


def _cmd_identify(a: argparse.Namespace) -> int:
    from ..commands import identify

    return identify.main(a)


def register_identify(sub) -> None:
    p = command(
        sub,
        "identify",
        "identify a model file from a folder of runs",
        reads="RUNS/*.csv and their JSON sidecars (docs/data-format.md: PRBS, constant-speed\n"
        "runs with loads, Stribeck speeds, open-loop force, variable speed,\n"
        "pre-rolling); --truth: a model file",
        writes="OUT (the identified model file, JSON; with --bootstrap, with intervals);\n"
        "refuses an existing file without --force; the identified values on stdout",
        example="feeddrive identify runs --out model.json",
    )
    path_argument(
        p, RUNS, "runs", help="folder of recordings (for instance from `feeddrive experiments`)"
    )
    path_argument(p, OUT_FILE, "--out", required=True, help="model file to write (JSON)")
    path_argument(
        p,
        FILE,
        "--truth",
        default=None,
        help="model file of the truth (virtual runs): print true vs identified",
    )
    p.add_argument(
        "--bootstrap",
        type=REPLICATES,
        default=None,
        metavar="N",
        help="N replicates: intervals in the model file (see --interval-method)",
    )
    p.add_argument(
        "--interval-method",
        choices=INTERVAL_METHODS,
        default=INTERVAL_METHODS[0],
        help="parametric: campaigns simulated on the identified model, bias-corrected "
        "intervals (N >= 10); runs: percentiles over whole runs resampled within "
        "cells of repeats (noise spread only, no bias)",
    )
    p.add_argument(
        "--level", type=LEVEL, default=0.95, help="coverage of the bootstrap intervals (0..1)"
    )
    p.add_argument("--seed", type=SEED, default=0, help="bootstrap seed (>= 0)")
    p.add_argument(
        "--workers", type=STEPS, default=None, help="worker processes (default: one per core)"
    )
    p.add_argument(
        "--scheduler", default=None, help="address of a Dask scheduler (default: a LocalCluster)"
    )
    p.add_argument(
        "--serial", action="store_true", help="every replicate in this process (no Dask)"
    )
    progress_argument(p)
    p.add_argument(
        "--position-friction",
        action="store_true",
        help="also identify the friction-level profile p(x) (effect position_friction) "
        "from the constant-speed runs (not with --bootstrap)",
    )
    force_argument(p, "file")
    p.set_defaults(func=_cmd_identify)


def _cmd_diagnose(a: argparse.Namespace) -> int:
    from ..commands import diagnose

    return diagnose.main(a)


def register_diagnose(sub) -> None:
    p = command(
        sub,
        "diagnose",
        "find the effects the model lacks (force residual, held-out blocks)",
        reads="RUNS (recordings: CSV and JSON sidecars, docs/data-format.md);\n"
        "--model: the starting model file",
        writes="OUT/diagnosis.json, OUT/model.json (the confirmed effects),\n"
        "OUT/model_all_fits.json, OUT/report.html; the steps and verdict on stdout",
        example="feeddrive diagnose runs/cv_p30mm_s_P0.csv runs/variable_speed.csv \\\n"
        "    --model model.json --out diag",
    )
    path_argument(
        p,
        RUN,
        "runs",
        nargs="+",
        type=Path,
        help="measured runs (CSV recordings, docs/data-format.md)",
    )
    path_argument(p, FILE, "--model", required=True, type=Path, help="starting model file (JSON)")
    path_argument(p, OUT_DIR, "--out", required=True, type=Path, help="output folder")
    p.add_argument("--max-steps", type=STEPS, default=4, help="at most this many effects (>= 1)")
    p.add_argument(
        "--force-gain",
        type=POSITIVE,
        default=None,
        help="N/V for runs without a current column (else the sidecar's "
        "'force_gain', else the model's current loop)",
    )
    p.add_argument(
        "--window",
        type=WINDOW,
        default=None,
        help="Savitzky-Golay window of the acceleration [samples, odd >= 5] (default 20 ms)",
    )
    p.add_argument("--blocks", type=BLOCKS, default=10, help="held-out blocks over all runs (>= 2)")
    p.add_argument(
        "--no-closed-loop",
        action="store_true",
        help="skip the closed-loop re-simulation of runs with a known controller",
    )
    force_argument(p)
    progress_argument(p)
    p.set_defaults(func=_cmd_diagnose)


def _cmd_sweep(a: argparse.Namespace) -> int:
    from ..commands import sweep

    return sweep.main(a)


def register_sweep(sub) -> None:
    p = command(
        sub,
        "sweep",
        "a parameter study (STUDY.json) on Dask: table, sensitivities, report",
        reads="STUDY (JSON, schema feeddrive.study/1) and the model file, recording or\n"
        "runs folder it names",
        writes="OUT/results.csv, OUT/results.parquet, OUT/report.html; the sensitivities\n"
        "on stdout",
        example="feeddrive sweep friction_study.json --out build/study --workers 2",
    )
    path_argument(p, STUDY, "study", type=Path, help="study file (JSON, schema feeddrive.study/1)")
    path_argument(
        p,
        OUT_DIR,
        "--out",
        required=True,
        type=Path,
        help="output folder (results.csv/.parquet, report.html)",
    )
    p.add_argument(
        "--scheduler", default=None, help="address of a Dask scheduler (default: a LocalCluster)"
    )
    p.add_argument(
        "--workers", type=STEPS, default=None, help="worker processes (default: one per core)"
    )
    p.add_argument(
        "--resume",
        action="store_true",
        help="keep the finished rows in --out, compute the missing runs",
    )
    p.add_argument("--serial", action="store_true", help="every run in this process (no Dask)")
    p.add_argument(
        "--force", action="store_true", help="start again: replace the results already in --out"
    )
    progress_argument(p)
    p.set_defaults(func=_cmd_sweep)
