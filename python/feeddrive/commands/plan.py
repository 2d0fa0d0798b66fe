"""`feeddrive plan`: the identification campaign as references and sidecars for a real drive."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..experiments.plan.files import plan_command, summary


def main(a: argparse.Namespace) -> int:
    """Run ``feeddrive plan`` with the parsed arguments ``a``; returns the exit status."""
    plan, size = plan_command(
        Path(a.out),
        a.model,
        a.controller,
        a.stroke,
        a.v_max,
        a.a_max,
        a.u_limit,
        a.loads,
        force=a.force,
        html=a.html,
    )
    print(summary(plan, a.out, size))
    return 0
