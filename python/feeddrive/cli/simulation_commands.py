"""The parsers of the simulation commands (run, report, model, system, circle, validate,
experiments, fmu): each command's arguments, help and example, and the call of its work."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from .arguments import (
    BUILD,
    FEEDFORWARD_CHOICES,
    FILE,
    MISMATCH_CHOICES,
    OUT_DIR,
    OUT_FILE,
    POSITIVE,
    REPEATS,
    RUN,
    RUN_FORMATS,
    RUNS,
    SEED,
    SHARED_ENV,
    SYSTEM_CASES,
    TREE,
    command,
    force_argument,
    path_argument,
    progress_argument,
)

# each command's work (feeddrive.commands.<name>) is imported only when the command runs


def _cmd_run(a: argparse.Namespace) -> int:
    from ..commands import run

    return run.main(a)


def register_run(sub) -> None:
    p = command(
        sub,
        "run",
        "the main job: the paper's Secs. 3 and 4 reproduced, the report "
        "written and its tables printed",
        reads="the plant FMU; with --runs, a folder of recordings (docs/data-format.md);\n"
        "with --shared, DIR/realdata/odrive-cogging (the ODrive cogging maps)",
        writes="OUT/index.html with its figures (PNG) and sec3_measured.csv; the tables on\n"
        "stdout (tracking errors in µm)",
        example="feeddrive run --out build/report --shared /data/feeddrive-shared --force",
    )
    path_argument(
        p,
        OUT_DIR,
        "--out",
        default=str(BUILD / "report"),
        help="output folder (default build/report)",
    )
    path_argument(
        p,
        RUNS,
        "--runs",
        default=None,
        help="folder of identification runs whose figures are added to the report",
    )
    path_argument(
        p,
        TREE,
        "--shared",
        default=os.environ.get(SHARED_ENV) or None,
        help=f"the shared data folder (holds realdata/odrive-cogging); default ${SHARED_ENV}",
    )
    force_argument(p)
    progress_argument(p)
    p.set_defaults(func=_cmd_run)


def _cmd_report(a: argparse.Namespace) -> int:
    from ..commands import report

    return report.main(a)


def register_report(sub) -> None:
    p = command(
        sub,
        "report",
        "the identification report of a folder of recordings: the "
        "figures of the paper's Figs. 5-13 (no reproductions)",
        reads="RUNS/*.csv and their JSON sidecars (docs/data-format.md); --truth: a model file",
        writes="OUT/index.html with its figures (PNG) and OUT/model.json (the identified model)",
        example="feeddrive experiments --out runs\n"
        "feeddrive report runs --out build/identification",
    )
    path_argument(
        p,
        RUNS,
        "runs",
        type=Path,
        help="folder of recordings (for instance from `feeddrive experiments`)",
    )
    path_argument(
        p,
        OUT_DIR,
        "--out",
        type=Path,
        default=BUILD / "identification",
        help="output folder (default build/identification)",
    )
    path_argument(
        p,
        FILE,
        "--truth",
        default=None,
        help="model file the runs came from (virtual runs): adds true vs identified",
    )
    force_argument(p)
    progress_argument(p)
    p.set_defaults(func=_cmd_report)


def _cmd_model(a: argparse.Namespace) -> int:
    from ..commands import model

    return model.main(a)


def register_model(sub) -> None:
    p = command(
        sub,
        "model",
        "write a model file (JSON: effects and parameters)",
        reads="nothing",
        writes="OUT (a model file, JSON); refuses an existing file without --force",
        example="feeddrive model --paper --out paper.json",
    )
    p.add_argument("--paper", action="store_true", help="the paper's full model")
    p.add_argument("--emps", action="store_true", help="the EMPS benchmark authors' rigid baseline")
    path_argument(
        p, OUT_FILE, "--out", default="model.json", help="model file to write (default model.json)"
    )
    force_argument(p, "file")
    p.set_defaults(func=_cmd_model)


def _cmd_system(a: argparse.Namespace) -> int:
    from ..commands import system

    return system.main(a)


def register_system(sub) -> None:
    p = command(
        sub,
        "system",
        "write the closed loop as SSP, OSP and container FMU",
        reads="the plant FMU",
        writes="OUT/<case>.ssp, OUT/<case>_osp/, OUT/<case>_container.fmu; with --run, the\n"
        "agreement of libcosim and fmpy with the harness (µm) on stdout",
        example="feeddrive system --case sec3 --out build/system --run",
    )
    p.add_argument(
        "--case",
        choices=SYSTEM_CASES,
        default="sec3",
        help="the loop: Sec. 3 (state space), Sec. 4 with GMS or static-friction "
        "feedforward (default sec3)",
    )
    path_argument(
        p,
        OUT_DIR,
        "--out",
        default=str(BUILD / "system"),
        help="output folder (default build/system)",
    )
    p.add_argument(
        "--run",
        action="store_true",
        help="run them in libcosim and fmpy and compare with the harness",
    )
    p.add_argument(
        "--force", action="store_true", help="replace the case's files in --out if they exist"
    )
    progress_argument(p)
    p.set_defaults(func=_cmd_system)


def _cmd_circle(a: argparse.Namespace) -> int:
    from ..commands import circle

    return circle.main(a)


def register_circle(sub) -> None:
    p = command(
        sub,
        "circle",
        "the ISO 230-4 circular test on the X-Y table: G, H, quadrant glitches, polar plots",
        reads="the plant and controller FMUs; --x-model, --y-model: model files",
        writes="OUT/index.html and a polar plot per case (circle_*.png); with --osp, OUT/osp/;\n"
        "the table of G, H and glitches (µm) on stdout",
        example="feeddrive circle --radius-mm 10 --feed-m-min 1 --out build/circle",
    )
    p.add_argument(
        "--radius-mm",
        type=POSITIVE,
        nargs="+",
        default=[10.0, 50.0],
        help="circle radii [mm] (default 10 50)",
    )
    p.add_argument(
        "--feed-m-min",
        type=POSITIVE,
        nargs="+",
        default=[1.0, 5.0],
        help="feeds [m/min] (default 1 5)",
    )
    p.add_argument(
        "--direction",
        nargs="+",
        choices=("ccw", "cw"),
        default=["ccw", "cw"],
        help="contouring directions (H needs both)",
    )
    p.add_argument(
        "--feedforward",
        nargs="+",
        choices=FEEDFORWARD_CHOICES,
        default=["none", "gms"],
        help="feedforward cases (default none gms)",
    )
    path_argument(
        p,
        FILE,
        "--x-model",
        type=Path,
        default=None,
        help="model file of the X axis (default: the paper's drive)",
    )
    path_argument(
        p,
        FILE,
        "--y-model",
        type=Path,
        default=None,
        help="model file of the Y axis (default: the paper's drive, 40 kg, friction x1.5, magnets +9.375 mm)",
    )
    p.add_argument(
        "--mismatch",
        choices=MISMATCH_CHOICES,
        default="sec4",
        help="plant = nominal x the Sec. 4 mismatch (default), or the nominal itself",
    )
    p.add_argument(
        "--osp",
        action="store_true",
        help="also write each circle as an OSP system structure (4 FMUs) for libcosim in OUT/osp/",
    )
    path_argument(
        p,
        OUT_DIR,
        "--out",
        default=str(BUILD / "circle"),
        help="output folder (default build/circle: index.html, circle_*.png)",
    )
    force_argument(p)
    progress_argument(p)
    p.set_defaults(func=_cmd_circle)


def _cmd_validate(a: argparse.Namespace) -> int:
    from ..commands import validate

    return validate.main(a)


def register_validate(sub) -> None:
    p = command(
        sub,
        "validate",
        "replay a measured run through model and controller and print the gap",
        reads="MEASURED (a recording: CSV and its JSON sidecar, docs/data-format.md);\n"
        "--model: a model file (default: the paper's model)",
        writes="nothing; prints the position gap x_sim - x_meas (µm) and the force\nresidual (N)",
        example="feeddrive validate runs/variable_speed.csv --model model.json",
    )
    path_argument(p, RUN, "measured", help="the recording to replay (CSV with time,u,x[,i,x_ref])")
    path_argument(p, FILE, "--model", default=None, help="model file (default: the paper's model)")
    progress_argument(p)
    p.set_defaults(func=_cmd_validate)


def _cmd_experiments(a: argparse.Namespace) -> int:
    from ..commands import experiments

    return experiments.main(a)


def register_experiments(sub) -> None:
    p = command(
        sub,
        "experiments",
        "write the identification experiments as virtual runs",
        reads="the plant FMU; --model: a model file (default: the paper's model)",
        writes="OUT/*.csv and their JSON sidecars (docs/data-format.md), one per run",
        example="feeddrive experiments --out runs --repeats 3",
    )
    path_argument(p, OUT_DIR, "--out", required=True, help="output folder of the recordings")
    path_argument(
        p, FILE, "--model", default=None, help="model file to simulate (default: the paper's model)"
    )
    p.add_argument("--seed", type=SEED, default=1, help="noise seed (>= 0)")
    p.add_argument(
        "--repeats",
        type=REPEATS,
        default=1,
        help="runs of every experiment with independent noise (for identify --bootstrap)",
    )
    p.add_argument(
        "--format",
        choices=RUN_FORMATS,
        default=RUN_FORMATS[0],
        help="file format of the runs: gzip-compressed CSV (default) or plain CSV",
    )
    force_argument(p)
    progress_argument(p)
    p.set_defaults(func=_cmd_experiments)


def _cmd_fmu(a: argparse.Namespace) -> int:
    from ..commands import fmu

    return fmu.main(a)


def register_fmu(sub) -> None:
    p = command(
        sub,
        "fmu",
        "write a model file as its own plant FMU (its start values) and an "
        "SSP parameter set (.ssv) beside it",
        reads="MODEL (a model file, JSON) and the packaged plant FMU",
        writes="OUT (NAME.fmu, FMI 2.0 or 3.0) and NAME.ssv beside it; refuses an existing\n"
        "file without --force",
        example="feeddrive fmu model.json --out MyDrive.fmu --fmi 2",
    )
    path_argument(
        p, FILE, "model", type=Path, help="model file (JSON), e.g. from `feeddrive identify`"
    )
    path_argument(
        p,
        OUT_FILE,
        "--out",
        required=True,
        type=Path,
        help="the FMU to write (NAME.fmu; NAME.ssv beside it)",
    )
    p.add_argument("--fmi", type=int, choices=(2, 3), default=2, help="FMI version (default 2)")
    force_argument(p, "file")
    p.set_defaults(func=_cmd_fmu)
