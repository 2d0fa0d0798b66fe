"""What the commands share: the usage error, progress bars on stderr (quiet off a terminal or
with ``--no-progress``), the check of an output file (``--force``)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterable
from pathlib import Path

from tqdm import tqdm

from ..outputs import OutputError, check_file


class UsageError(ValueError):
    """A command was given arguments it cannot use."""


def progress_enabled(a: argparse.Namespace) -> bool:
    """Progress bars: on a terminal (stderr) unless ``--no-progress``."""
    return not getattr(a, "no_progress", False) and sys.stderr.isatty()


def bar(items: Iterable, desc: str, unit: str, a: argparse.Namespace) -> tqdm:
    """``items`` behind a tqdm bar on stderr (quiet off a terminal or with --no-progress)."""
    return tqdm(items, desc=desc, unit=unit, disable=not progress_enabled(a))


class stages:
    """A tqdm bar of named stages (elapsed time shown): ``with stages(desc, a) as stage:``,
    then ``stage(name)`` as each stage starts; quiet off a terminal or with --no-progress."""

    def __init__(self, desc: str, a: argparse.Namespace) -> None:
        self.desc, self.enabled = desc, progress_enabled(a)
        self.bar: tqdm | None = None

    def __enter__(self) -> stages:
        if self.enabled:
            self.bar = tqdm(
                desc=self.desc, unit="stage", bar_format="{desc}: {n} stages, {elapsed} {postfix}"
            )
        return self

    def __call__(self, name: str) -> None:
        if self.bar is not None:
            self.bar.set_postfix_str(name, refresh=False)
            self.bar.update(1)

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.close()


def check_out_file(path: Path, inputs: list, force: bool) -> Path:
    """An output file: writable and none of ``inputs`` (:func:`feeddrive.outputs.check_file`),
    and not an existing file unless ``force``."""
    out = check_file(path, inputs)
    if out.exists() and not force:
        raise OutputError(f"{out}: exists; give --force to replace it, or another --out")
    return out
