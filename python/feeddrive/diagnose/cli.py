"""``feeddrive diagnose MEASURED.csv [MORE.csv ...] --model MODEL.json --out DIR`` (the lead's
CLI calls :func:`run_cli`)."""
from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

from ..data import load_run
from ..model_file import load_model
from .residual import DEFAULT_WINDOW
from .workflow import diagnose


def parser(prog: str = "feeddrive diagnose") -> argparse.ArgumentParser:
    """The argument parser of the diagnose command."""
    p = argparse.ArgumentParser(prog=prog, description="Find which effects a model lacks "
                                "against measured runs (force residual, held-out blocks).")
    p.add_argument("runs", nargs="+", type=Path, help="measured runs (DATA.md CSV files)")
    p.add_argument("--model", required=True, type=Path, help="starting model file (JSON)")
    p.add_argument("--out", required=True, type=Path, help="output directory")
    p.add_argument("--max-steps", type=int, default=4, help="at most this many effects")
    p.add_argument("--force-gain", type=float, default=None,
                   help="N/V for runs without a current column (else the sidecar's "
                        "'force_gain', else the model's current loop)")
    p.add_argument("--window", type=int, default=DEFAULT_WINDOW,
                   help="Savitzky-Golay window of the acceleration [samples]")
    p.add_argument("--blocks", type=int, default=10, help="held-out blocks over all runs")
    p.add_argument("--no-closed-loop", action="store_true",
                   help="skip the closed-loop re-simulation of runs with a known controller")
    return p


def run_cli(argv: Sequence[str] | None = None) -> int:
    """Parse ``argv``, run the diagnosis, write DIR/{diagnosis.json,model.json,report.html},
    print a summary; returns the exit status."""
    args = parser().parse_args(argv)
    runs = [load_run(p) for p in args.runs]
    model = load_model(args.model)
    diag = diagnose(runs, model, out_dir=args.out, max_steps=args.max_steps,
                    force_gain=args.force_gain, window=args.window, n_blocks=args.blocks,
                    closed_loop=not args.no_closed_loop)
    for note in diag.notes:
        print(note)
    for k, s in enumerate(diag.steps, 1):
        amb = f" (cannot be told from {', '.join(s.ambiguous_with)})" if s.ambiguous_with else ""
        print(f"step {k}: {s.effect}{amb}: held-out improvement "
              f"{s.evidence['heldout_improvement']:.1%}, t = {s.evidence['t_blocks']:.1f}; "
              f"force gap {s.gap_before['force_rms_N']:.3g} N -> "
              f"{s.gap_after['force_rms_N']:.3g} N")
    print(f"stopped: {diag.stop.get('reason')}")
    print(f"wrote {args.out / 'diagnosis.json'}, {args.out / 'model.json'}, "
          f"{args.out / 'report.html'}")
    return 0
