"""How fast the command line answers: ``feeddrive --help`` and ``feeddrive CMD --help`` for
every command, each in a fresh interpreter, against ``python -c "import numpy"`` measured in
the same loop (the target: at most twice that).

``python -m feeddrive.bench_cli`` prints the table; :func:`help_rows` gives the rows of
``make bench``.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time

from .cli import build_parser

#: the target: every --help within this many times the start of ``python -c "import numpy"``
TARGET_RATIO = 2.0


def commands() -> list[str]:
    """Every sub-command of ``feeddrive``."""
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return list(sub.choices)


def _wall(argv: list[str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def help_times(repeats: int = 5, python: str = sys.executable) -> tuple[float, dict[str, float]]:
    """Median wall time [s] of ``import numpy`` and of each ``--help`` (key "" for the top
    level), over ``repeats`` rounds that run every command once (a load spike hits them all)."""
    names = ["", *commands()]
    walls: dict[str, list[float]] = {n: [] for n in names}
    numpy: list[float] = []
    for _ in range(repeats):
        numpy.append(_wall([python, "-c", "import numpy"]))
        for n in names:
            walls[n].append(_wall([python, "-m", "feeddrive.cli", *([n] if n else []), "--help"]))
    return statistics.median(numpy), {n: statistics.median(w) for n, w in walls.items()}


def help_rows(repeats: int = 5) -> list[tuple[str, str, str]]:
    """Rows (what, measured, target) of ``make bench``: the baseline, the top level, the
    slowest command's help, and every command's time."""
    numpy, walls = help_times(repeats)
    top = walls.pop("")
    slow = max(walls, key=lambda c: walls[c])
    target = f"<= {TARGET_RATIO:g}x import numpy"
    every = ", ".join(f"{n} {w * 1e3:.0f}" for n, w in walls.items())
    return [
        (
            f'python -c "import numpy" (fresh interpreter, median of {repeats})',
            f"{numpy * 1e3:.0f} ms",
            "",
        ),
        ("feeddrive --help", f"{top * 1e3:.0f} ms, {top / numpy:.2f}x import numpy", target),
        (
            f"feeddrive CMD --help, the slowest ({slow}); every command [ms]: {every}",
            f"{walls[slow] * 1e3:.0f} ms, {walls[slow] / numpy:.2f}x import numpy",
            target,
        ),
    ]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=5, help="rounds (the median is kept)")
    a = ap.parse_args(argv)
    print("| what | measured | target |\n|---|---|---|")
    for row in help_rows(a.repeats):
        print("| " + " | ".join(row) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
