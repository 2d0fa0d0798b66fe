"""The README and docs/ document what the FMU declares (variables table generated from the XML) and
link only to files in the repository."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_readme_variables_table_is_current():
    p = subprocess.run(
        [
            sys.executable,
            str(ROOT / "tools" / "vars_table.py"),
            "--check",
            str(ROOT / "docs" / "variables.md"),
            str(ROOT / "docs" / "parameters.md"),
        ],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 0, p.stdout + p.stderr


def test_readme_shows_the_two_commands():
    text = (ROOT / "README.md").read_text()
    assert "make run" in text and "make test" in text


def test_user_docs_link_only_inside_the_repository():
    import re

    for f in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        text = f.read_text()
        assert "../shared" not in text, f
        for target in re.findall(r"\]\(([^)#:]+)(?:#[^)]*)?\)", text):
            assert (f.parent / target).exists(), (f, target)


def test_readme_is_short_with_a_picture_the_project_made():
    import re

    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= 200
    pictures = re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", text)
    assert pictures and all((ROOT / p).stat().st_size < 100_000 for p in pictures), pictures
