"""The command line's shared pieces: the roles of path arguments and the guard that no
command writes over what it reads, the checked number types of the options, the parser class
with one-line errors, ``--version``, and the helpers every command's registration uses.

Standard library only, so that ``feeddrive --help`` answers at once.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from ..inputs import one_line

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


def path_argument(p: argparse.ArgumentParser, role: str, *flags: str, **kw) -> argparse.Action:
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
    from ..harness.controller_fmu import CONTROLLER_FMU_ENV, DEFAULT_CONTROLLER_FMU
    from ..model_description import DEFAULT_FMU, FMU_ENV
    from ..outputs import Reads

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
        from ..study import study_reads  # dask: only for the commands that read a study

        for study in got[STUDY]:
            reads = reads + study_reads(study)
    return reads


def check_outputs(a: argparse.Namespace, roles: dict[str, str]) -> None:
    """The guard run before every command: each output option (a file or a folder) against
    everything the command reads (:func:`feeddrive.outputs.check_not_input`)."""
    from ..outputs import check_not_input

    reads = command_reads(a, roles)
    for dest, role in roles.items():
        if role in OUTPUT_ROLES and getattr(a, dest, None) is not None:
            check_not_input(getattr(a, dest), reads, folder=role == OUT_DIR)


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line (no usage block), exit status 2."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {one_line(message)} ({self.prog} --help: the options)\n")


class Version(argparse.Action):
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
        from .. import __version__

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


POSITIVE = _number(float, "a finite number > 0", lambda v: 0 < v < float("inf"))
FINITE = _number(float, "a finite number", lambda v: abs(v) < float("inf"))
STEPS = _number(int, "an integer >= 1", lambda v: v >= 1)
BLOCKS = _number(int, "an integer >= 2", lambda v: v >= 2)
WINDOW = _number(int, "an odd integer >= 5 [samples]", lambda v: v >= 5 and v % 2 == 1)
SEED = _number(int, "an integer >= 0", lambda v: v >= 0)
REPLICATES = _number(int, "an integer >= 2", lambda v: v >= 2)
LEVEL = _number(float, "a number in (0, 1)", lambda v: 0 < v < 1)
REPEATS = _number(int, f"an integer in [1, {MAX_REPEATS}]", lambda v: 1 <= v <= MAX_REPEATS)


def command(
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


def force_argument(p: argparse.ArgumentParser, what: str = "folder") -> None:
    text = (
        "replace --out if it exists"
        if what == "file"
        else "replace --out when it is a non-empty folder feeddrive did not write"
    )
    p.add_argument("--force", action="store_true", help=text)


def progress_argument(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--no-progress",
        action="store_true",
        help="no progress bar (there is none either when stderr is not a terminal)",
    )
