"""The product speaks of itself: no sentence of the code, comments, docs or examples refers to
the history of the work that made it (a tracker's issue or item, a planning card), and what a
user reads (the package, the FMU sources, docs, examples, tools) names no file outside the
repository."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: phrases a user cannot look up (this file, which spells them out, is not scanned)
PHRASES = re.compile(
    "|".join(
        [
            r"\bissue\s*#?\d+",  # "issue 13", "issue #4"
            r"\bitem\s+\d+",  # "item 6"
            r"\bthe\s+issue(?:'s|\s+asks|\s+sets)",
            r"\bidentification\s+issue",
            r"\bdesign\s+card",
        ]
    ),
    re.I,
)

SUFFIXES = {
    ".py",
    ".c",
    ".h",
    ".md",
    ".xml",
    ".json",
    ".toml",
    ".yml",
    ".yaml",
    ".txt",
    ".java",
    ".map",
    "",
}


def _product_files() -> list[Path]:
    out = subprocess.run(
        ["git", "ls-files", "-co", "--exclude-standard"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    files = [
        ROOT / f
        for f in out
        if not f.startswith("tests/c/corpus/") and f != "tests/test_product_words.py"
    ]
    return [f for f in files if f.is_file() and (f.suffix in SUFFIXES or f.name == "Makefile")]


def test_no_sentence_refers_to_the_history_of_the_work():
    hits = []
    for f in _product_files():
        try:
            text = f.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue
        for n, line in enumerate(text.splitlines(), 1):
            if PHRASES.search(line):
                hits.append(f"{f.relative_to(ROOT)}:{n}: {line.strip()[:100]}")
    assert not hits, "\n".join(hits)


def test_the_pattern_finds_what_it_is_for():
    for s in [
        "see issue 13",
        "Issue #4 says",
        "item 6 of",
        "the issue's figure",
        "the design card",
    ]:
        assert PHRASES.search(s), s
    for s in ["an issue of precision", "each item of the list", "the issue of scale"]:
        assert not PHRASES.search(s), s


#: notes that live outside the repository (the project's working notes beside the checkout)
OUTSIDE = re.compile(r"\b(?:MODEL|DATA|EFFECTS|ARCHITECTURE)\.md\b|\.\./shared\b")
USER_READ = (
    "python/",
    "fmu_src/",
    "docs/",
    "examples/",
    "tools/",
    "README.md",
    "CHANGELOG.md",
    "modelDescription.xml",
    "mkdocs.yml",
)


def test_what_a_user_reads_names_no_file_outside_the_repository():
    hits = []
    for f in _product_files():
        rel = f.relative_to(ROOT).as_posix()
        if not rel.startswith(USER_READ):
            continue
        for n, line in enumerate(f.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
            if OUTSIDE.search(line):
                hits.append(f"{rel}:{n}: {line.strip()[:100]}")
    assert not hits, "\n".join(hits)
