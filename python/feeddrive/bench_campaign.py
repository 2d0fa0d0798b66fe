"""`make bench` row of the default identification campaign: what `feeddrive experiments`
writes (size on disk, compressed and as plain CSV) and how long it takes."""

from __future__ import annotations

import struct
import tempfile
import time
from pathlib import Path

from .data import run_files
from .data_csv import is_compressed
from .experiments.campaign import write_campaign

#: the default campaign's size on disk [bytes] (runs and sidecars)
CAMPAIGN_TARGET_BYTES = 60e6


def _plain_size(path: Path) -> int:
    """The CSV text size of a recording: a ``.gz`` file's ISIZE field (its last 4 bytes,
    the uncompressed length modulo 2**32; one member, < 4 GiB), else the file's size."""
    if not is_compressed(path):
        return path.stat().st_size
    with open(path, "rb") as f:
        f.seek(-4, 2)
        return struct.unpack("<I", f.read(4))[0]


def campaign_rows(seed: int = 1) -> list[tuple[str, str, str]]:
    """Run the default campaign (paper model, default format) into a temporary folder."""
    with tempfile.TemporaryDirectory(prefix="feeddrive_bench_campaign_") as d:
        out = Path(d) / "runs"
        t0 = time.perf_counter()
        write_campaign(out, seed=seed)
        wall = time.perf_counter() - t0
        files = [p for p in out.iterdir() if p.is_file() and not p.name.startswith(".")]
        runs = run_files(out)
        size = sum(p.stat().st_size for p in files)
        plain = size - sum(p.stat().st_size for p in runs) + sum(_plain_size(p) for p in runs)
        largest = max(runs, key=lambda p: p.stat().st_size)
        ok = "met" if size <= CAMPAIGN_TARGET_BYTES else "MISSED"
        return [
            (
                f"default campaign (`feeddrive experiments`, {len(runs)} runs, .csv.gz)",
                f"{size / 1e6:.1f} MB ({ok}), {plain / 1e6:.0f} MB as plain CSV (--format csv)",
                f"<= {CAMPAIGN_TARGET_BYTES / 1e6:.0f} MB",
            ),
            ("  its largest run", f"{largest.name}: {largest.stat().st_size / 1e6:.1f} MB", ""),
            ("  wall time of the campaign (simulation and writing)", f"{wall:.0f} s", ""),
        ]
