"""`feeddrive` command line: thin over the modules (model, experiments, identification,
validation, diagnosis, report)."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .fmu import REPO
from .model_file import ModelFileError

BUILD = REPO / "build"


def _cmd_model(a: argparse.Namespace) -> int:
    from .model_file import paper_model, save_model
    out = Path(a.out)
    if a.paper:
        save_model(paper_model(), out)
        print(f"wrote {out}: the paper's full model; edit its \"effects\" map for reduced models")
    elif a.emps:
        from .diagnose.emps import emps_baseline_model
        save_model(emps_baseline_model(), out)
        print(f"wrote {out}: the EMPS authors' rigid baseline (use --force-gain 35.15 with its runs)")
    else:
        print("feeddrive model: give --paper (the paper's full model) or --emps (EMPS baseline)",
              file=sys.stderr)
        return 2
    return 0


def _cmd_report(a: argparse.Namespace) -> int:
    from .validation.workflow import main_job
    main_job(Path(a.out), print_tables=a.command == "run", runs_dir=Path(a.runs) if a.runs else None)
    return 0


def _cmd_validate(a: argparse.Namespace) -> int:
    from .validation.replay import validate_file
    rep = validate_file(Path(a.measured), Path(a.model) if a.model else None)
    print(rep.text())
    return 0


def _cmd_experiments(a: argparse.Namespace) -> int:
    from .experiments.campaign import write_campaign
    paths = write_campaign(Path(a.out), model=Path(a.model) if a.model else None, seed=a.seed)
    print(f"wrote {len(paths)} runs to {a.out}")
    return 0


def _cmd_identify(a: argparse.Namespace) -> int:
    from .identify.pipeline import identify_folder
    from .model_file import load_model
    truth = load_model(Path(a.truth)).fmu_parameters() if a.truth else None
    try:
        res = identify_folder(Path(a.runs), Path(a.out), truth=truth)
    except (ValueError, FileNotFoundError) as e:
        print(f"feeddrive identify: {e}", file=sys.stderr)
        return 2
    print(res.text())
    return 0


def _cmd_diagnose(a: argparse.Namespace) -> int:
    from .diagnose.cli import run_cli
    return int(run_cli(a) or 0)


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="feeddrive", description=__doc__)
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="the main job: Secs. 3 and 4 reproduced, report written, tables printed")
    p.add_argument("--out", default=str(BUILD / "report"))
    p.add_argument("--runs", default=None, help="folder of identification runs to add to the report")
    p.set_defaults(func=_cmd_report)
    p = sub.add_parser("report", help="write build/report/index.html (figures and tables)")
    p.add_argument("--out", default=str(BUILD / "report"))
    p.add_argument("--runs", default=None, help="folder of identification runs to add to the report")
    p.set_defaults(func=_cmd_report)
    p = sub.add_parser("model", help="write a model file")
    p.add_argument("--paper", action="store_true", help="the paper's full model")
    p.add_argument("--emps", action="store_true", help="the EMPS benchmark authors' rigid baseline")
    p.add_argument("--out", default="model.json")
    p.set_defaults(func=_cmd_model)
    p = sub.add_parser("validate", help="replay a measured run through model and controller")
    p.add_argument("measured")
    p.add_argument("--model", default=None)
    p.set_defaults(func=_cmd_validate)
    p = sub.add_parser("experiments", help="write the identification experiments as virtual runs")
    p.add_argument("--out", required=True)
    p.add_argument("--model", default=None)
    p.add_argument("--seed", type=int, default=1)
    p.set_defaults(func=_cmd_experiments)
    p = sub.add_parser("identify", help="identify a model file from a folder of runs")
    p.add_argument("runs")
    p.add_argument("--out", required=True)
    p.add_argument("--truth", default=None, help="model file of the truth (virtual runs): print true vs identified")
    p.set_defaults(func=_cmd_identify)
    p = sub.add_parser("diagnose", help="find the effects the model lacks")
    from .diagnose.cli import add_arguments
    add_arguments(p)
    p.set_defaults(func=_cmd_diagnose)
    return ap


def main(argv: list[str] | None = None) -> int:
    a = build_parser().parse_args(argv)
    try:
        return a.func(a)
    except ModelFileError as e:          # a model file the FMU would refuse, or malformed
        print(f"feeddrive {a.command}: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
