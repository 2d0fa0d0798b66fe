"""The README documents what the FMU declares (variables table generated from the XML)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_readme_variables_table_is_current():
    p = subprocess.run([sys.executable, str(ROOT / "tools" / "vars_table.py"), "--check", str(ROOT / "README.md")],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr


def test_readme_shows_the_two_commands():
    text = (ROOT / "README.md").read_text()
    assert "make run" in text and "make test" in text
