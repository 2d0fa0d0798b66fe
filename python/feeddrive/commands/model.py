"""`feeddrive model`: write a model file (the paper's full model, or the EMPS baseline)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..diagnose.emps import emps_baseline_model
from ..model_file import paper_model, save_model
from .common import UsageError, check_out_file


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive model`` with the parsed arguments ``a``; returns the exit status."""
    out = check_out_file(Path(a.out), [], a.force)
    if a.paper and a.emps:
        raise UsageError("give one of --paper and --emps")
    if a.paper:
        save_model(paper_model(), out)
        print(f'wrote {out}: the paper\'s full model; edit its "effects" map for reduced models')
    elif a.emps:
        save_model(emps_baseline_model(), out)
        print(
            f"wrote {out}: the EMPS authors' rigid baseline (use --force-gain 35.15 with its runs)"
        )
    else:
        raise UsageError("give --paper (the paper's full model) or --emps (EMPS baseline)")
    return 0
