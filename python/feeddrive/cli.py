"""`feeddrive` command line: parses the arguments and calls the modules (model, experiments,
identification, validation, diagnosis, report).

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
from collections.abc import Sequence
from pathlib import Path

from .data import load_run, load_runs, sidecar_path
from .diagnose.emps import emps_baseline_model
from .diagnose.workflow import diagnose
from .experiments.campaign import MAX_REPEATS, write_campaign
from .fmu import FMUError, fmu_path
from .harness.controller_fmu import (CONTROLLER_FMU_ENV, DEFAULT_CONTROLLER_FMU,
                                     controller_fmu_path)
from .identify.pipeline import identify_folder
from .inputs import one_line
from .model_description import DEFAULT_FMU, FMU_ENV
from .model_file import load_model, paper_model, save_model
from .outputs import Reads, check_dir, check_file, check_not_input, output_dir
from .report.circle import write_circle_report
from .report.diagnosis import write_diagnosis
from .report.main_job import main_job
from .report.study import write_bootstrap_report, write_study_report
from .study import BootstrapStudy, load_study_file, run_bootstrap_study, run_study, study_reads
from .study.bootstrap import bootstrap_folder
from .systems import sec3_system, sec4_system, write_all
from .systems.compare import compare_engines
from .systems.xy_system import circle_system, write_xy_osp
from .validation.circle_test import (FEEDFORWARD, MIN_PER_M_S, check_fits, circle_table,
                                    circular_case)
from .validation.replay import check_run, validate_file
from .validation.xy_machine import MISMATCH, xy_axes

BUILD = Path("build")           # relative to the working directory
SHARED_ENV = "FEEDDRIVE_SHARED"


#: roles of the path arguments: a run CSV (and its sidecar), a folder of runs (every
#: ``*.csv`` and its sidecar), a file (model file), a folder read as a whole (nothing may be
#: written inside it), a study file (and the files it names); a file or folder written
RUN, RUNS, FILE, TREE, STUDY, OUT_FILE, OUT_DIR = ("run", "runs", "file", "tree", "study",
                                                   "out-file", "out-dir")
OUTPUT_ROLES = (OUT_FILE, OUT_DIR)
_ROLE = "feeddrive_role"


def _path(p: argparse.ArgumentParser, role: str, *flags: str, **kw) -> argparse.Action:
    """Add a path argument with its ``role`` (what the guard reads from it or checks)."""
    action = p.add_argument(*flags, **kw)
    setattr(action, _ROLE, role)
    return action


def path_roles(parser: argparse.ArgumentParser) -> dict[str, dict[str, str]]:
    """Every sub-command of ``parser`` -> {argument dest: role} of its path arguments."""
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {name: {a.dest: getattr(a, _ROLE) for a in p._actions if hasattr(a, _ROLE)}
            for name, p in sub.choices.items()}


def command_reads(a: argparse.Namespace, roles: dict[str, str]) -> Reads:
    """Everything the command of ``a`` reads: the files behind its path arguments (by role)
    and the plant and controller FMUs."""
    got: dict[str, list] = {RUN: [], RUNS: [], FILE: [], TREE: [], STUDY: []}
    for dest, role in roles.items():
        value = getattr(a, dest, None)
        if role in got and value is not None:
            got[role] += value if isinstance(value, list) else [value]
    fmus = [os.environ.get(FMU_ENV) or DEFAULT_FMU,
            os.environ.get(CONTROLLER_FMU_ENV) or DEFAULT_CONTROLLER_FMU]
    reads = Reads.of(files=got[FILE] + fmus, runs=got[RUN], run_folders=got[RUNS],
                     trees=got[TREE])
    for study in got[STUDY]:
        reads = reads + study_reads(study)
    return reads


def check_outputs(a: argparse.Namespace, roles: dict[str, str]) -> None:
    """The guard run before every command: each output option (a file or a folder) against
    everything the command reads (:func:`feeddrive.outputs.check_not_input`)."""
    reads = command_reads(a, roles)
    for dest, role in roles.items():
        if role in OUTPUT_ROLES and getattr(a, dest, None) is not None:
            check_not_input(getattr(a, dest), reads, folder=role == OUT_DIR)


class _Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line (no usage block), exit status 2."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {one_line(message)} ({self.prog} --help: the options)\n")


class UsageError(ValueError):
    """A command was given arguments it cannot use."""


def _number(kind: type, rule: str, ok):
    """An argparse type: ``kind`` (int or float) checked by ``ok``; the message says ``rule``."""
    def parse(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not {'an integer' if kind is int else 'a number'}") from None
        if not ok(value):
            raise argparse.ArgumentTypeError(f"{text} is out of range: must be {rule}")
        return value
    parse.__name__ = "integer" if kind is int else "number"
    return parse


_POSITIVE = _number(float, "a finite number > 0", lambda v: 0 < v < float("inf"))
_STEPS = _number(int, "an integer >= 1", lambda v: v >= 1)
_BLOCKS = _number(int, "an integer >= 2", lambda v: v >= 2)
_WINDOW = _number(int, "an odd integer >= 5 [samples]", lambda v: v >= 5 and v % 2 == 1)
_SEED = _number(int, "an integer >= 0", lambda v: v >= 0)
_REPLICATES = _number(int, "an integer >= 2", lambda v: v >= 2)
_LEVEL = _number(float, "a number in (0, 1)", lambda v: 0 < v < 1)
_REPEATS = _number(int, f"an integer in [1, {MAX_REPEATS}]", lambda v: 1 <= v <= MAX_REPEATS)


def _cmd_model(a: argparse.Namespace) -> int:
    out = check_file(Path(a.out))
    if a.paper and a.emps:
        raise UsageError("give one of --paper and --emps")
    if a.paper:
        save_model(paper_model(), out)
        print(f"wrote {out}: the paper's full model; edit its \"effects\" map for reduced models")
    elif a.emps:
        save_model(emps_baseline_model(), out)
        print(f"wrote {out}: the EMPS authors' rigid baseline (use --force-gain 35.15 with its runs)")
    else:
        raise UsageError("give --paper (the paper's full model) or --emps (EMPS baseline)")
    return 0


def _cmd_report(a: argparse.Namespace) -> int:
    fmu_path()      # no FMU: one line before the job starts
    check_dir(Path(a.out), [a.runs, a.shared], a.force)
    for run in load_runs(a.runs) if a.runs else ():
        check_run(run)      # a bad run: one line now, not after the reproductions
    main_job(Path(a.out), print_tables=a.command == "run", runs_dir=Path(a.runs) if a.runs else None,
             shared_dir=Path(a.shared) if a.shared else None, force=a.force)
    return 0


SYSTEMS = {"sec3": sec3_system, "sec4_gms": lambda: sec4_system("gms"),
           "sec4_static": lambda: sec4_system("static")}


def _cmd_system(a: argparse.Namespace) -> int:
    fmu_path()
    system = SYSTEMS[a.case]()
    files = write_all(system, Path(a.out))
    for kind, path in files.items():
        print(f"wrote {path} ({kind})")
    if a.run:
        print("\n".join(compare_engines(system, files)))
    return 0


def _cmd_circle(a: argparse.Namespace) -> int:
    fmu_path()
    controller_fmu_path()        # no FMU: one line before the runs
    axes = xy_axes(a.x_model, a.y_model, a.mismatch)       # a bad model file: one line now
    radii = [r * 1e-3 for r in a.radius_mm]
    for r in radii:
        check_fits(axes, r)
    directions = list(dict.fromkeys(a.direction))
    with output_dir(Path(a.out), [a.x_model, a.y_model], a.force, what="circle") as stage:
        cases = [circular_case(axes, r, f / MIN_PER_M_S, ff, directions)
                 for r in radii for f in a.feed_m_min for ff in dict.fromkeys(a.feedforward)]
        lines = [f"axis {ax.name}: {ax.source} (m = {ax.nominal['m']:g} kg); plant = nominal "
                 + ("x Sec. 4 mismatch" if a.mismatch == "sec4" else "(no mismatch)")
                 for ax in axes]
        write_circle_report(cases, stage, lines)
        osp = [write_xy_osp(sy, stage / "osp" / sy.name).parent.name
               for sy in (circle_system(axes, c.radius, c.feed, d, c.feedforward)
                          for c in cases for d in directions)] if a.osp else []
    print(circle_table(cases))
    print("\n".join(lines))
    print(f"wrote {Path(a.out) / 'index.html'} and {len(cases)} polar plots (circle_*.png)")
    if osp:
        print(f"wrote {len(osp)} OSP system structures for libcosim (4 FMUs each): "
              f"{Path(a.out) / 'osp' / osp[0] / 'OspSystemStructure.xml'}, ...")
    return 0


def _cmd_validate(a: argparse.Namespace) -> int:
    rep = validate_file(Path(a.measured), Path(a.model) if a.model else None)
    print(rep.text())
    return 0


def _cmd_experiments(a: argparse.Namespace) -> int:
    paths = write_campaign(Path(a.out), model=Path(a.model) if a.model else None, seed=a.seed,
                           force=a.force, repeats=a.repeats)
    print(f"wrote {len(paths)} runs to {a.out}")
    return 0


def _cmd_identify(a: argparse.Namespace) -> int:
    if a.position_friction and a.bootstrap is not None:
        raise ValueError("--position-friction is not available with --bootstrap "
                         "(the bootstrap repeats the paper's steps 1-6)")
    check_file(Path(a.out), [a.truth])
    truth = load_model(Path(a.truth)).fmu_parameters() if a.truth else None
    if a.bootstrap is None:
        res = identify_folder(Path(a.runs), Path(a.out), truth=truth,
                              position_friction=a.position_friction)
        print(res.text())
        return 0
    res, boot = bootstrap_folder(Path(a.runs), Path(a.out), a.bootstrap, seed=a.seed,
                                 level=a.level, truth=truth, scheduler=a.scheduler,
                                 workers=a.workers, parallel=not a.serial,
                                 progress=not a.no_progress, method=a.interval_method)
    print(res.text())
    print(boot.text())
    return 0


def _cmd_diagnose(a: argparse.Namespace) -> int:
    inputs = [a.model, *a.runs, *(sidecar_path(p) for p in a.runs)]
    check_dir(a.out, inputs, a.force)
    runs = [load_run(p) for p in a.runs]
    model = load_model(a.model)
    for run in runs:
        check_run(run, model)
    diag = diagnose(runs, model, max_steps=a.max_steps, force_gain=a.force_gain,
                    window=a.window, n_blocks=a.blocks, closed_loop=not a.no_closed_loop)
    report = write_diagnosis(diag, a.out, inputs, a.force)
    for note in diag.notes:
        print(note)
    for k, s in enumerate(diag.steps, 1):
        amb = f" (cannot be told from {', '.join(s.ambiguous_with)})" if s.ambiguous_with else ""
        print(f"step {k}: {s.decision} {s.effect}{amb}: held-out improvement "
              f"{s.evidence['heldout_improvement']:.1%}, t = {s.evidence['t_blocks']:.1f}; "
              f"force gap {s.gap_before['force_rms_N']:.3g} N -> "
              f"{s.gap_after['force_rms_N']:.3g} N")
    print(f"stopped: {diag.stop.get('reason')}")
    print(f"verdict: {diag.verdict['verdict']}: {diag.verdict['sentence']}")
    for rec in diag.confirmation.get("steps", []):
        print(f"{rec['effect']}: {'confirmed' if rec['confirmed'] else 'not confirmed'}: {rec['why']}")
    mj, ma = diag.confirmation["model_json"], diag.confirmation["model_all_fits_json"]
    print(f"model.json: the confirmed effects ({', '.join(mj['effects_added']) or 'none added'}), "
          f"force gap {mj['gap_N']:.3g} N; model_all_fits.json: every fit "
          f"({', '.join(ma['effects_added']) or 'none added'}), force gap {ma['gap_N']:.3g} N")
    print(f"wrote {a.out / 'diagnosis.json'}, {a.out / 'model.json'}, "
          f"{a.out / 'model_all_fits.json'}, {report}")
    return 0


def _cmd_sweep(a: argparse.Namespace) -> int:
    study = load_study_file(a.study)
    if a.workers is not None and a.workers < 1:
        raise UsageError(f"--workers {a.workers}: must be >= 1")
    if isinstance(study, BootstrapStudy):
        if a.resume:
            raise UsageError(f"--resume: {a.study} is a bootstrap study (kind 'bootstrap'), written "
                             "whole at the end; run it again without --resume")
        boot = run_bootstrap_study(study, a.out, scheduler=a.scheduler, workers=a.workers,
                                   parallel=not a.serial, progress=not a.no_progress)
        report = write_bootstrap_report(boot, a.out)
        print(boot.summary())
        print(f"wrote {report}")
        return 0
    try:
        res = run_study(study, a.out, scheduler=a.scheduler, workers=a.workers, resume=a.resume,
                        progress=not a.no_progress, parallel=not a.serial)
    except KeyboardInterrupt:
        print(f"feeddrive sweep: interrupted; the finished runs are in {a.out / 'results.csv'}: "
              f"run again with --resume", file=sys.stderr)
        return 130
    report = write_study_report(res, a.out)
    print(res.summary())
    print(f"wrote {report}")
    return 0


def _diagnose_arguments(p: argparse.ArgumentParser) -> None:
    _path(p, RUN, "runs", nargs="+", type=Path, help="measured runs (CSV recordings, docs/data-format.md)")
    _path(p, FILE, "--model", required=True, type=Path, help="starting model file (JSON)")
    _path(p, OUT_DIR, "--out", required=True, type=Path, help="output directory")
    p.add_argument("--max-steps", type=_STEPS, default=4, help="at most this many effects (>= 1)")
    p.add_argument("--force-gain", type=_POSITIVE, default=None,
                   help="N/V for runs without a current column (else the sidecar's "
                        "'force_gain', else the model's current loop)")
    p.add_argument("--window", type=_WINDOW, default=None,
                   help="Savitzky-Golay window of the acceleration [samples, odd >= 5] (default 20 ms)")
    p.add_argument("--blocks", type=_BLOCKS, default=10, help="held-out blocks over all runs (>= 2)")
    p.add_argument("--no-closed-loop", action="store_true",
                   help="skip the closed-loop re-simulation of runs with a known controller")
    _force_argument(p)


def _force_argument(p: argparse.ArgumentParser) -> None:
    p.add_argument("--force", action="store_true",
                   help="replace a non-empty --out folder that feeddrive did not write")


def build_parser() -> argparse.ArgumentParser:
    """The parser of every ``feeddrive`` sub-command."""
    ap = _Parser(prog="feeddrive", description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    for name, text in (("run", "the main job: Secs. 3 and 4 reproduced, report written, tables printed"),
                       ("report", "write build/report/index.html (figures and tables)")):
        p = sub.add_parser(name, help=text)
        _path(p, OUT_DIR, "--out", default=str(BUILD / "report"))
        _path(p, RUNS, "--runs", default=None, help="folder of identification runs to add to the report")
        _path(p, TREE, "--shared", default=os.environ.get(SHARED_ENV) or None,
                       help=f"the shared data folder (holds realdata/odrive-cogging); default ${SHARED_ENV}")
        _force_argument(p)
        p.set_defaults(func=_cmd_report)
    p = sub.add_parser("model", help="write a model file")
    p.add_argument("--paper", action="store_true", help="the paper's full model")
    p.add_argument("--emps", action="store_true", help="the EMPS benchmark authors' rigid baseline")
    _path(p, OUT_FILE, "--out", default="model.json")
    p.set_defaults(func=_cmd_model)
    p = sub.add_parser("system", help="write the closed loop as SSP, OSP and container FMU")
    p.add_argument("--case", choices=sorted(SYSTEMS), default="sec3")
    _path(p, OUT_DIR, "--out", default=str(BUILD / "system"))
    p.add_argument("--run", action="store_true",
                   help="run them in libcosim and fmpy and compare with the harness")
    p.set_defaults(func=_cmd_system)
    p = sub.add_parser("circle", help="the ISO 230-4 circular test on the X-Y table: G, H, "
                                      "quadrant glitches, polar plots")
    p.add_argument("--radius-mm", type=_POSITIVE, nargs="+", default=[10.0, 50.0],
                   help="circle radii [mm] (default 10 50)")
    p.add_argument("--feed-m-min", type=_POSITIVE, nargs="+", default=[1.0, 5.0],
                   help="feeds [m/min] (default 1 5)")
    p.add_argument("--direction", nargs="+", choices=("ccw", "cw"), default=["ccw", "cw"],
                   help="contouring directions (H needs both)")
    p.add_argument("--feedforward", nargs="+", choices=sorted(FEEDFORWARD), default=["none", "gms"],
                   help="feedforward cases (default none gms)")
    _path(p, FILE, "--x-model", type=Path, default=None, help="model file of the X axis (default: the paper's drive)")
    _path(p, FILE, "--y-model", type=Path, default=None,
                   help="model file of the Y axis (default: the paper's drive, 40 kg, friction x1.5, magnets +9.375 mm)")
    p.add_argument("--mismatch", choices=MISMATCH, default="sec4",
                   help="plant = nominal x the Sec. 4 mismatch (default), or the nominal itself")
    p.add_argument("--osp", action="store_true",
                   help="also write each circle as an OSP system structure (4 FMUs) for libcosim in OUT/osp/")
    _path(p, OUT_DIR, "--out", default=str(BUILD / "circle"), help="output folder (index.html, circle_*.png)")
    _force_argument(p)
    p.set_defaults(func=_cmd_circle)
    p = sub.add_parser("validate", help="replay a measured run through model and controller")
    _path(p, RUN, "measured")
    _path(p, FILE, "--model", default=None)
    p.set_defaults(func=_cmd_validate)
    p = sub.add_parser("experiments", help="write the identification experiments as virtual runs")
    _path(p, OUT_DIR, "--out", required=True)
    _path(p, FILE, "--model", default=None)
    p.add_argument("--seed", type=_SEED, default=1, help="noise seed (>= 0)")
    p.add_argument("--repeats", type=_REPEATS, default=1,
                   help="runs of every experiment with independent noise (for identify --bootstrap)")
    _force_argument(p)
    p.set_defaults(func=_cmd_experiments)
    p = sub.add_parser("identify", help="identify a model file from a folder of runs")
    _path(p, RUNS, "runs")
    _path(p, OUT_FILE, "--out", required=True)
    _path(p, FILE, "--truth", default=None, help="model file of the truth (virtual runs): print true vs identified")
    p.add_argument("--bootstrap", type=_REPLICATES, default=None, metavar="N",
                   help="N replicates: intervals in the model file (see --interval-method)")
    p.add_argument("--interval-method", choices=("parametric", "runs"), default="parametric",
                   help="parametric: campaigns simulated on the identified model, bias-corrected "
                        "intervals (N >= 10); runs: percentiles over whole runs resampled within "
                        "cells of repeats (noise spread only, no bias)")
    p.add_argument("--level", type=_LEVEL, default=0.95, help="coverage of the bootstrap intervals (0..1)")
    p.add_argument("--seed", type=_SEED, default=0, help="bootstrap seed (>= 0)")
    p.add_argument("--workers", type=_STEPS, default=None, help="LocalCluster worker processes (default: one per core)")
    p.add_argument("--scheduler", default=None, help="address of a Dask scheduler (default: a LocalCluster)")
    p.add_argument("--serial", action="store_true", help="every replicate in this process (no Dask)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--position-friction", action="store_true",
                   help="also identify the friction-level profile p(x) (effect position_friction) "
                        "from the constant-speed runs (not with --bootstrap)")
    p.set_defaults(func=_cmd_identify)
    p = sub.add_parser("diagnose", help="find the effects the model lacks (force residual, held-out blocks)")
    _diagnose_arguments(p)
    p.set_defaults(func=_cmd_diagnose)
    p = sub.add_parser("sweep", help="a parameter study (STUDY.json) on Dask: table, sensitivities, report")
    _path(p, STUDY, "study", type=Path, help="study file (JSON, schema feeddrive.study/1)")
    _path(p, OUT_DIR, "--out", required=True, type=Path, help="output folder (results.csv/.parquet, report.html)")
    p.add_argument("--scheduler", default=None, help="address of a Dask scheduler (default: a LocalCluster)")
    p.add_argument("--workers", type=int, default=None, help="LocalCluster worker processes (default: one per core)")
    p.add_argument("--resume", action="store_true", help="keep the finished rows in --out, compute the missing runs")
    p.add_argument("--serial", action="store_true", help="every run in this process (no Dask)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_sweep)
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    """Run one ``feeddrive`` command; returns its exit status (2: bad input, one line on stderr)."""
    parser = build_parser()
    a = parser.parse_args(argv)
    try:
        check_outputs(a, path_roles(parser)[a.command])
        return int(a.func(a) or 0)
    except (ValueError, OSError, FMUError) as e:
        print(f"feeddrive {a.command}: {one_line(str(e))}", file=sys.stderr)
        return 2
    except ImportError as e:            # an optional engine (libcosimpy) is not installed
        print(f"feeddrive {a.command}: {one_line(str(e.name or e))} is not installed "
              "(pip install 'feeddrive[test]' brings the engines)", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
