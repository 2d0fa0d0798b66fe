"""``feeddrive diagnose MEASURED.csv [MORE.csv ...] --model MODEL.json --out DIR`` (the lead's
CLI calls :func:`run_cli`)."""
from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from ..data import load_run
from ..model_file import load_model
from .workflow import diagnose


def parser(prog: str = "feeddrive diagnose") -> argparse.ArgumentParser:
    """The argument parser of the diagnose command."""
    p = argparse.ArgumentParser(prog=prog, description="Find which effects a model lacks "
                                "against measured runs (force residual, held-out blocks).")
    add_arguments(p)
    return p


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The diagnose command's arguments (also used by the package CLI's sub-command)."""
    p.add_argument("runs", nargs="+", type=Path, help="measured runs (DATA.md CSV files)")
    p.add_argument("--model", required=True, type=Path, help="starting model file (JSON)")
    p.add_argument("--out", required=True, type=Path, help="output directory")
    p.add_argument("--max-steps", type=int, default=4, help="at most this many effects")
    p.add_argument("--force-gain", type=float, default=None,
                   help="N/V for runs without a current column (else the sidecar's "
                        "'force_gain', else the model's current loop)")
    p.add_argument("--window", type=int, default=None,
                   help="Savitzky-Golay window of the acceleration [samples] (default 20 ms)")
    p.add_argument("--blocks", type=int, default=10, help="held-out blocks over all runs")
    p.add_argument("--no-closed-loop", action="store_true",
                   help="skip the closed-loop re-simulation of runs with a known controller")


def _from_namespace(a: argparse.Namespace) -> argparse.Namespace:
    """Fill what another parser (the package CLI's ``diagnose`` sub-command) left out."""
    runs = getattr(a, "runs", None) or getattr(a, "measured", None)
    if not runs:
        raise ValueError("feeddrive diagnose: no measured runs given")
    return argparse.Namespace(
        runs=[Path(p) for p in runs], model=Path(a.model), out=Path(a.out),
        max_steps=int(getattr(a, "max_steps", 4)), force_gain=getattr(a, "force_gain", None),
        window=getattr(a, "window", None), blocks=int(getattr(a, "blocks", 10)),
        no_closed_loop=bool(getattr(a, "no_closed_loop", False)))


def run_cli(argv: Sequence[str] | argparse.Namespace | None = None) -> int:
    """Run the diagnosis from an argv list (parsed by :func:`parser`) or an argparse
    namespace with ``measured``/``runs``, ``model``, ``out`` (and optionally the other
    options); write DIR/{diagnosis.json, model.json, report.html}; print a summary; returns
    the exit status (2 for bad input, with the message on stderr)."""
    args = _from_namespace(argv) if isinstance(argv, argparse.Namespace) \
        else parser().parse_args(argv)
    try:
        runs = [load_run(p) for p in args.runs]
        model = load_model(args.model)
        diag = diagnose(runs, model, out_dir=args.out, max_steps=args.max_steps,
                        force_gain=args.force_gain, window=args.window, n_blocks=args.blocks,
                        closed_loop=not args.no_closed_loop)
    except (ValueError, OSError) as e:
        print(f"feeddrive diagnose: {e}", file=sys.stderr)
        return 2
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
