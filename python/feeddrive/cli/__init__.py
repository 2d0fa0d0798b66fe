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
import sys
from collections.abc import Callable, Sequence

from ..inputs import one_line
from .arguments import (
    BUILD,
    FEEDFORWARD_CHOICES,
    FILE,
    INTERVAL_METHODS,
    MAX_REPEATS,
    MISMATCH_CHOICES,
    OUT_DIR,
    OUT_FILE,
    OUTPUT_ROLES,
    RUN,
    RUN_FORMATS,
    RUNS,
    SHARED_ENV,
    STEPS,
    STUDY,
    SYSTEM_CASES,
    TREE,
    Parser,
    Version,
    check_outputs,
    command_reads,
    path_roles,
    version,
)
from .data_commands import register_diagnose, register_identify, register_plan, register_sweep
from .simulation_commands import (
    register_circle,
    register_experiments,
    register_fmu,
    register_model,
    register_report,
    register_run,
    register_system,
    register_validate,
)

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


#: one registration function per command, in the order of ``feeddrive --help``
COMMANDS: tuple[Callable[[argparse._SubParsersAction], None], ...] = (
    register_run,
    register_report,
    register_model,
    register_system,
    register_circle,
    register_validate,
    register_experiments,
    register_plan,
    register_identify,
    register_diagnose,
    register_fmu,
    register_sweep,
)


def build_parser() -> argparse.ArgumentParser:
    """The parser of every ``feeddrive`` sub-command."""
    ap = Parser(
        prog="feeddrive",
        description=DESCRIPTION,
        epilog=_VOCABULARY,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument("--version", action=Version)
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for register in COMMANDS:
        register(sub)
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    """Run one ``feeddrive`` command; returns its exit status (2: bad input, one line on stderr)."""
    parser = build_parser()
    a = parser.parse_args(argv)
    from ..fmu import FMUError

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


__all__ = [
    "BUILD",
    "COMMANDS",
    "FEEDFORWARD_CHOICES",
    "FILE",
    "INTERVAL_METHODS",
    "MAX_REPEATS",
    "MISMATCH_CHOICES",
    "OUTPUT_ROLES",
    "OUT_DIR",
    "OUT_FILE",
    "RUN",
    "RUNS",
    "RUN_FORMATS",
    "SHARED_ENV",
    "STUDY",
    "SYSTEM_CASES",
    "TREE",
    "STEPS",
    "build_parser",
    "check_outputs",
    "command_reads",
    "main",
    "path_roles",
    "version",
]
