"""`feeddrive` command line: parses the arguments and calls the modules (model, experiments,
identification, validation, diagnosis, report).

The parser is built from the standard library only: every command's work (and the heavy
imports it needs: scipy, fmpy, matplotlib, dask, the package's stages) is imported inside the
function that runs it, so ``feeddrive --help`` and ``feeddrive CMD --help`` answer at once.
Each command has one registration function (its arguments, help, what it reads and writes,
an example) listed in :data:`COMMANDS`, and its work in a module of :mod:`feeddrive.commands`,
imported by a two-line ``_cmd_*`` function when the command runs.

One option vocabulary: ``--out`` is where a command writes (a file or a folder), ``--model``
a model file it reads, ``--force`` lets it replace an existing output, ``--workers`` the
number of worker processes.  No command replaces a file without ``--force`` (a folder
feeddrive wrote itself, marked by ``.feeddrive-output``, holds one run's results and is
replaced by the next run).

Bad input (a file, a field, a parameter) ends a command with one line on stderr naming it
and exit status 2, never a traceback; control characters of a file name are escaped in it.
Before a command starts, every output option is checked against everything the command reads
(:func:`check_outputs`, from the role of each path argument): no command writes over a file
it read.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from .inputs import one_line

BUILD = Path("build")  # relative to the working directory
SHARED_ENV = "FEEDDRIVE_SHARED"

#: the choices the parser offers, named here so that ``--help`` imports no stage; a test
#: checks them against the modules that define them (experiments.campaign.MAX_REPEATS,
#: xy.circle_test.FEEDFORWARD, xy.machine.MISMATCH, commands.system,
#: experiments.campaign.FORMATS, study.bootstrap.METHODS)
MAX_REPEATS = 100
RUN_FORMATS = ("csv.gz", "csv")
INTERVAL_METHODS = ("parametric", "runs")
FEEDFORWARD_CHOICES = ("gms", "none", "static")
MISMATCH_CHOICES = ("sec4", "none")
SYSTEM_CASES = ("sec3", "sec4_gms", "sec4_static", "sec3_delay1")

#: roles of the path arguments: a run CSV (and its sidecar), a folder of runs (every
#: ``*.csv`` and its sidecar), a file (model file), a folder read as a whole (nothing may be
#: written inside it), a study file (and the files it names); a file or folder written
RUN, RUNS, FILE, TREE, STUDY, OUT_FILE, OUT_DIR = (
    "run",
    "runs",
    "file",
    "tree",
    "study",
    "out-file",
    "out-dir",
)
OUTPUT_ROLES = (OUT_FILE, OUT_DIR)
_ROLE = "feeddrive_role"


#: how the help shows the value of a path option of each role
_METAVAR = {
    RUN: "RUN.csv",
    RUNS: "DIR",
    FILE: "FILE",
    TREE: "DIR",
    STUDY: "STUDY.json",
    OUT_FILE: "FILE",
    OUT_DIR: "DIR",
}


def _path(p: argparse.ArgumentParser, role: str, *flags: str, **kw) -> argparse.Action:
    """Add a path argument with its ``role`` (what the guard reads from it or checks)."""
    kw.setdefault("metavar", _METAVAR[role] if flags[0].startswith("-") else flags[0].upper())
    action = p.add_argument(*flags, **kw)
    setattr(action, _ROLE, role)
    return action


def path_roles(parser: argparse.ArgumentParser) -> dict[str, dict[str, str]]:
    """Every sub-command of ``parser`` -> {argument dest: role} of its path arguments."""
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {
        name: {a.dest: getattr(a, _ROLE) for a in p._actions if hasattr(a, _ROLE)}
        for name, p in sub.choices.items()
    }


def command_reads(a: argparse.Namespace, roles: dict[str, str]):
    """Everything the command of ``a`` reads (a :class:`feeddrive.outputs.Reads`): the files
    behind its path arguments (by role) and the plant and controller FMUs."""
    from .harness.controller_fmu import CONTROLLER_FMU_ENV, DEFAULT_CONTROLLER_FMU
    from .model_description import DEFAULT_FMU, FMU_ENV
    from .outputs import Reads

    got: dict[str, list] = {RUN: [], RUNS: [], FILE: [], TREE: [], STUDY: []}
    for dest, role in roles.items():
        value = getattr(a, dest, None)
        if role in got and value is not None:
            got[role] += value if isinstance(value, list) else [value]
    fmus = [
        os.environ.get(FMU_ENV) or DEFAULT_FMU,
        os.environ.get(CONTROLLER_FMU_ENV) or DEFAULT_CONTROLLER_FMU,
    ]
    reads = Reads.of(files=got[FILE] + fmus, runs=got[RUN], run_folders=got[RUNS], trees=got[TREE])
    if got[STUDY]:
        from .study import study_reads  # dask: only for the commands that read a study

        for study in got[STUDY]:
            reads = reads + study_reads(study)
    return reads


def check_outputs(a: argparse.Namespace, roles: dict[str, str]) -> None:
    """The guard run before every command: each output option (a file or a folder) against
    everything the command reads (:func:`feeddrive.outputs.check_not_input`)."""
    from .outputs import check_not_input

    reads = command_reads(a, roles)
    for dest, role in roles.items():
        if role in OUTPUT_ROLES and getattr(a, dest, None) is not None:
            check_not_input(getattr(a, dest), reads, folder=role == OUT_DIR)


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line (no usage block), exit status 2."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {one_line(message)} ({self.prog} --help: the options)\n")


class _Version(argparse.Action):
    """``--version``: the installed package's version (read only when asked)."""

    def __init__(
        self,
        option_strings,
        dest=argparse.SUPPRESS,
        default=argparse.SUPPRESS,
        help="print feeddrive's version and exit",
    ):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"feeddrive {version()}")
        parser.exit(0)


def version() -> str:
    """The version of the installed ``feeddrive`` distribution (the package's own without one)."""
    from importlib import metadata

    try:
        return metadata.version("feeddrive")
    except metadata.PackageNotFoundError:
        from . import __version__

        return __version__


def _number(kind: type, rule: str, ok):
    """An argparse type: ``kind`` (int or float) checked by ``ok``; the message says ``rule``."""

    def parse(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{text!r} is not {'an integer' if kind is int else 'a number'}"
            ) from None
        if not ok(value):
            raise argparse.ArgumentTypeError(f"{text} is out of range: must be {rule}")
        return value

    parse.__name__ = "integer" if kind is int else "number"
    return parse


_POSITIVE = _number(float, "a finite number > 0", lambda v: 0 < v < float("inf"))
_FINITE = _number(float, "a finite number", lambda v: abs(v) < float("inf"))
_STEPS = _number(int, "an integer >= 1", lambda v: v >= 1)
_BLOCKS = _number(int, "an integer >= 2", lambda v: v >= 2)
_WINDOW = _number(int, "an odd integer >= 5 [samples]", lambda v: v >= 5 and v % 2 == 1)
_SEED = _number(int, "an integer >= 0", lambda v: v >= 0)
_REPLICATES = _number(int, "an integer >= 2", lambda v: v >= 2)
_LEVEL = _number(float, "a number in (0, 1)", lambda v: 0 < v < 1)
_REPEATS = _number(int, f"an integer in [1, {MAX_REPEATS}]", lambda v: 1 <= v <= MAX_REPEATS)


# ---------------------------------------------------------------- the commands' work
# each command's module (feeddrive.commands.*) is imported only when the command runs


def _cmd_run(a: argparse.Namespace) -> int:
    from .commands import run

    return run.main(a)


def _cmd_report(a: argparse.Namespace) -> int:
    from .commands import report

    return report.main(a)


def _cmd_model(a: argparse.Namespace) -> int:
    from .commands import model

    return model.main(a)


def _cmd_system(a: argparse.Namespace) -> int:
    from .commands import system

    return system.main(a)


def _cmd_circle(a: argparse.Namespace) -> int:
    from .commands import circle

    return circle.main(a)


def _cmd_validate(a: argparse.Namespace) -> int:
    from .commands import validate

    return validate.main(a)


def _cmd_experiments(a: argparse.Namespace) -> int:
    from .commands import experiments

    return experiments.main(a)


def _cmd_fmu(a: argparse.Namespace) -> int:
    from .commands import fmu

    return fmu.main(a)


def _cmd_plan(a: argparse.Namespace) -> int:
    from .commands import plan

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


def _cmd_identify(a: argparse.Namespace) -> int:
    from .commands import identify

    return identify.main(a)


def _cmd_diagnose(a: argparse.Namespace) -> int:
    from .commands import diagnose

    return diagnose.main(a)


def _cmd_sweep(a: argparse.Namespace) -> int:
    from .commands import sweep

    return sweep.main(a)


# ---------------------------------------------------------------- the parser

DESCRIPTION = (
    "feeddrive: the linear-motor feed drive of Villegas et al. (2014) as FMUs, and the "
    "workflow around it: reproduce the paper, simulate experiments, identify a "
    "machine's parameters from recordings, validate in closed loop, diagnose what "
    "a model lacks."
)

_VOCABULARY = """\
options every command uses in the same sense:
  --out PATH     where the command writes (a file or a folder)
  --model FILE   a model file it reads (JSON; `feeddrive model` writes one)
  --force        replace an existing output (without it no file is replaced; a folder
                 feeddrive wrote, marked by .feeddrive-output, is replaced by the next run)
  --workers N    worker processes (default: one per core)

a first session:
  feeddrive run --out build/report            the paper's Secs. 3 and 4 reproduced
  feeddrive experiments --out runs            the identification experiments as recordings
  feeddrive identify runs --out model.json    a model file identified from them
  feeddrive diagnose runs/cv_p30mm_s_P0.csv runs/variable_speed.csv --model model.json --out diag
  feeddrive CMD --help                        what CMD reads, writes, and an example

recordings: CSV columns time,u,x[,i,x_ref,...] in SI units (s, V, m, A) with an optional
JSON sidecar; the format is in docs/data-format.md."""


def _command(
    sub, name: str, summary: str, *, reads: str, writes: str, example: str
) -> argparse.ArgumentParser:
    """A sub-command whose help says what it does, reads and writes, and shows an example."""
    epilog = f"reads:\n{_indent(reads)}\nwrites:\n{_indent(writes)}\nexample:\n{_indent(example)}"
    return sub.add_parser(
        name,
        help=summary,
        description=summary[:1].upper() + summary[1:] + ".",
        epilog=epilog,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )


def _indent(text: str) -> str:
    return "\n".join("  " + line for line in text.strip("\n").splitlines())


def _force_argument(p: argparse.ArgumentParser, what: str = "folder") -> None:
    text = (
        "replace --out if it exists"
        if what == "file"
        else "replace --out when it is a non-empty folder feeddrive did not write"
    )
    p.add_argument("--force", action="store_true", help=text)


def _progress_argument(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress bar (there is none either when stderr is not a terminal)",
    )


def _register_run(sub) -> None:
    p = _command(
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
    _path(
        p,
        OUT_DIR,
        "--out",
        default=str(BUILD / "report"),
        help="output folder (default build/report)",
    )
    _path(
        p,
        RUNS,
        "--runs",
        default=None,
        help="folder of identification runs whose figures are added to the report",
    )
    _path(
        p,
        TREE,
        "--shared",
        default=os.environ.get(SHARED_ENV) or None,
        help=f"the shared data folder (holds realdata/odrive-cogging); default ${SHARED_ENV}",
    )
    _force_argument(p)
    _progress_argument(p)
    p.set_defaults(func=_cmd_run)


def _register_report(sub) -> None:
    p = _command(
        sub,
        "report",
        "the identification report of a folder of recordings: the "
        "figures of the paper's Figs. 5-13 (no reproductions)",
        reads="RUNS/*.csv and their JSON sidecars (docs/data-format.md); --truth: a model file",
        writes="OUT/index.html with its figures (PNG) and OUT/model.json (the identified model)",
        example="feeddrive experiments --out runs\n"
        "feeddrive report runs --out build/identification",
    )
    _path(
        p,
        RUNS,
        "runs",
        type=Path,
        help="folder of recordings (for instance from `feeddrive experiments`)",
    )
    _path(
        p,
        OUT_DIR,
        "--out",
        type=Path,
        default=BUILD / "identification",
        help="output folder (default build/identification)",
    )
    _path(
        p,
        FILE,
        "--truth",
        default=None,
        help="model file the runs came from (virtual runs): adds true vs identified",
    )
    _force_argument(p)
    _progress_argument(p)
    p.set_defaults(func=_cmd_report)


def _register_model(sub) -> None:
    p = _command(
        sub,
        "model",
        "write a model file (JSON: effects and parameters)",
        reads="nothing",
        writes="OUT (a model file, JSON); refuses an existing file without --force",
        example="feeddrive model --paper --out paper.json",
    )
    p.add_argument("--paper", action="store_true", help="the paper's full model")
    p.add_argument("--emps", action="store_true", help="the EMPS benchmark authors' rigid baseline")
    _path(
        p, OUT_FILE, "--out", default="model.json", help="model file to write (default model.json)"
    )
    _force_argument(p, "file")
    p.set_defaults(func=_cmd_model)


def _register_system(sub) -> None:
    p = _command(
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
    _path(
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
    _progress_argument(p)
    p.set_defaults(func=_cmd_system)


def _register_circle(sub) -> None:
    p = _command(
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
        type=_POSITIVE,
        nargs="+",
        default=[10.0, 50.0],
        help="circle radii [mm] (default 10 50)",
    )
    p.add_argument(
        "--feed-m-min",
        type=_POSITIVE,
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
    _path(
        p,
        FILE,
        "--x-model",
        type=Path,
        default=None,
        help="model file of the X axis (default: the paper's drive)",
    )
    _path(
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
    _path(
        p,
        OUT_DIR,
        "--out",
        default=str(BUILD / "circle"),
        help="output folder (default build/circle: index.html, circle_*.png)",
    )
    _force_argument(p)
    _progress_argument(p)
    p.set_defaults(func=_cmd_circle)


def _register_validate(sub) -> None:
    p = _command(
        sub,
        "validate",
        "replay a measured run through model and controller and print the gap",
        reads="MEASURED (a recording: CSV and its JSON sidecar, docs/data-format.md);\n"
        "--model: a model file (default: the paper's model)",
        writes="nothing; prints the position gap x_sim - x_meas (µm) and the force\nresidual (N)",
        example="feeddrive validate runs/variable_speed.csv --model model.json",
    )
    _path(p, RUN, "measured", help="the recording to replay (CSV with time,u,x[,i,x_ref])")
    _path(p, FILE, "--model", default=None, help="model file (default: the paper's model)")
    _progress_argument(p)
    p.set_defaults(func=_cmd_validate)


def _register_experiments(sub) -> None:
    p = _command(
        sub,
        "experiments",
        "write the identification experiments as virtual runs",
        reads="the plant FMU; --model: a model file (default: the paper's model)",
        writes="OUT/*.csv and their JSON sidecars (docs/data-format.md), one per run",
        example="feeddrive experiments --out runs --repeats 3",
    )
    _path(p, OUT_DIR, "--out", required=True, help="output folder of the recordings")
    _path(
        p, FILE, "--model", default=None, help="model file to simulate (default: the paper's model)"
    )
    p.add_argument("--seed", type=_SEED, default=1, help="noise seed (>= 0)")
    p.add_argument(
        "--repeats",
        type=_REPEATS,
        default=1,
        help="runs of every experiment with independent noise (for identify --bootstrap)",
    )
    p.add_argument(
        "--format",
        choices=RUN_FORMATS,
        default=RUN_FORMATS[0],
        help="file format of the runs: gzip-compressed CSV (default) or plain CSV",
    )
    _force_argument(p)
    _progress_argument(p)
    p.set_defaults(func=_cmd_experiments)


def _register_plan(sub) -> None:
    p = _command(
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
    _path(p, OUT_DIR, "--out", required=True, help="output folder of the plan")
    _path(p, FILE, "--model", default=None, help="nominal model file (default: the paper's)")
    _path(
        p,
        FILE,
        "--controller",
        default=None,
        help="the drive's controller as a JSON spec for the sidecars (default: a PID with lead)",
    )
    p.add_argument(
        "--stroke",
        type=_FINITE,
        nargs=2,
        metavar=("X0", "X1"),
        default=None,
        help="usable stroke [m] (default: the model's)",
    )
    p.add_argument("--v-max", type=_POSITIVE, default=None, help="speed limit [m/s] (default 0.25)")
    p.add_argument(
        "--a-max", type=_POSITIVE, default=None, help="acceleration limit [m/s^2] (default 5)"
    )
    p.add_argument(
        "--u-limit",
        type=_POSITIVE,
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
    _force_argument(p)
    p.set_defaults(func=_cmd_plan)


def _register_fmu(sub) -> None:
    p = _command(
        sub,
        "fmu",
        "write a model file as its own plant FMU (its start values) and an "
        "SSP parameter set (.ssv) beside it",
        reads="MODEL (a model file, JSON) and the packaged plant FMU",
        writes="OUT (NAME.fmu, FMI 2.0 or 3.0) and NAME.ssv beside it; refuses an existing\n"
        "file without --force",
        example="feeddrive fmu model.json --out MyDrive.fmu --fmi 2",
    )
    _path(p, FILE, "model", type=Path, help="model file (JSON), e.g. from `feeddrive identify`")
    _path(
        p,
        OUT_FILE,
        "--out",
        required=True,
        type=Path,
        help="the FMU to write (NAME.fmu; NAME.ssv beside it)",
    )
    p.add_argument("--fmi", type=int, choices=(2, 3), default=2, help="FMI version (default 2)")
    _force_argument(p, "file")
    p.set_defaults(func=_cmd_fmu)


def _register_identify(sub) -> None:
    p = _command(
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
    _path(p, RUNS, "runs", help="folder of recordings (for instance from `feeddrive experiments`)")
    _path(p, OUT_FILE, "--out", required=True, help="model file to write (JSON)")
    _path(
        p,
        FILE,
        "--truth",
        default=None,
        help="model file of the truth (virtual runs): print true vs identified",
    )
    p.add_argument(
        "--bootstrap",
        type=_REPLICATES,
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
        "--level", type=_LEVEL, default=0.95, help="coverage of the bootstrap intervals (0..1)"
    )
    p.add_argument("--seed", type=_SEED, default=0, help="bootstrap seed (>= 0)")
    p.add_argument(
        "--workers", type=_STEPS, default=None, help="worker processes (default: one per core)"
    )
    p.add_argument(
        "--scheduler", default=None, help="address of a Dask scheduler (default: a LocalCluster)"
    )
    p.add_argument(
        "--serial", action="store_true", help="every replicate in this process (no Dask)"
    )
    _progress_argument(p)
    p.add_argument(
        "--position-friction",
        action="store_true",
        help="also identify the friction-level profile p(x) (effect position_friction) "
        "from the constant-speed runs (not with --bootstrap)",
    )
    _force_argument(p, "file")
    p.set_defaults(func=_cmd_identify)


def _register_diagnose(sub) -> None:
    p = _command(
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
    _path(
        p,
        RUN,
        "runs",
        nargs="+",
        type=Path,
        help="measured runs (CSV recordings, docs/data-format.md)",
    )
    _path(p, FILE, "--model", required=True, type=Path, help="starting model file (JSON)")
    _path(p, OUT_DIR, "--out", required=True, type=Path, help="output folder")
    p.add_argument("--max-steps", type=_STEPS, default=4, help="at most this many effects (>= 1)")
    p.add_argument(
        "--force-gain",
        type=_POSITIVE,
        default=None,
        help="N/V for runs without a current column (else the sidecar's "
        "'force_gain', else the model's current loop)",
    )
    p.add_argument(
        "--window",
        type=_WINDOW,
        default=None,
        help="Savitzky-Golay window of the acceleration [samples, odd >= 5] (default 20 ms)",
    )
    p.add_argument(
        "--blocks", type=_BLOCKS, default=10, help="held-out blocks over all runs (>= 2)"
    )
    p.add_argument(
        "--no-closed-loop",
        action="store_true",
        help="skip the closed-loop re-simulation of runs with a known controller",
    )
    _force_argument(p)
    _progress_argument(p)
    p.set_defaults(func=_cmd_diagnose)


def _register_sweep(sub) -> None:
    p = _command(
        sub,
        "sweep",
        "a parameter study (STUDY.json) on Dask: table, sensitivities, report",
        reads="STUDY (JSON, schema feeddrive.study/1) and the model file, recording or\n"
        "runs folder it names",
        writes="OUT/results.csv, OUT/results.parquet, OUT/report.html; the sensitivities\n"
        "on stdout",
        example="feeddrive sweep friction_study.json --out build/study --workers 2",
    )
    _path(p, STUDY, "study", type=Path, help="study file (JSON, schema feeddrive.study/1)")
    _path(
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
        "--workers", type=_STEPS, default=None, help="worker processes (default: one per core)"
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
    _progress_argument(p)
    p.set_defaults(func=_cmd_sweep)


#: one registration function per command, in the order of ``feeddrive --help``
COMMANDS: tuple[Callable[[argparse._SubParsersAction], None], ...] = (
    _register_run,
    _register_report,
    _register_model,
    _register_system,
    _register_circle,
    _register_validate,
    _register_experiments,
    _register_plan,
    _register_identify,
    _register_diagnose,
    _register_fmu,
    _register_sweep,
)


def build_parser() -> argparse.ArgumentParser:
    """The parser of every ``feeddrive`` sub-command."""
    ap = _Parser(
        prog="feeddrive",
        description=DESCRIPTION,
        epilog=_VOCABULARY,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument("--version", action=_Version)
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for register in COMMANDS:
        register(sub)
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    """Run one ``feeddrive`` command; returns its exit status (2: bad input, one line on stderr)."""
    parser = build_parser()
    a = parser.parse_args(argv)
    from .fmu import FMUError

    try:
        check_outputs(a, path_roles(parser)[a.command])
        return int(a.func(a) or 0)
    except (ValueError, OSError, FMUError) as e:
        print(f"feeddrive {a.command}: {one_line(str(e))}", file=sys.stderr)
        return 2
    except ImportError as e:  # an optional engine (libcosimpy) is not installed
        print(
            f"feeddrive {a.command}: {one_line(str(e.name or e))} is not installed "
            "(pip install 'feeddrive[test]' brings the engines)",
            file=sys.stderr,
        )
        return 2


if __name__ == "__main__":
    sys.exit(main())
