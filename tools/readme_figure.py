#!/usr/bin/env python3
"""Write docs/img/sec3_reversal.png, the picture of the README and the docs' home page: the
report's Fig. 14 analogue (feeddrive.report.closed_loop_figures.fig14) of the Sec. 3
reproduction (feeddrive.experiments.sec3.reproduce), at a size for a web page.

Usage: readme_figure.py [OUT.png]
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

from feeddrive.experiments.sec3 import reproduce
from feeddrive.report.closed_loop_figures import fig14

ROOT = Path(__file__).resolve().parents[1]


def main() -> int:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs" / "img" / "sec3_reversal.png"
    fig = fig14(reproduce())
    fig.savefig(out, dpi=72)
    print(f"wrote {out} ({out.stat().st_size // 1024} KiB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
