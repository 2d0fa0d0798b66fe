"""tools/patch_fmipp.py (make importers' patch of fmipp's sdist setup.py): every edit applied
once; a setup.py without one of the texts stops with the text named."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools"))
from patch_fmipp import EDITS, main, patch

SETUP = "".join(f"# part {k}\n{old}" for k, (old, _) in enumerate(EDITS))


def test_patch_removes_sundials_and_the_export_modules() -> None:
    out = patch(SETUP)
    assert "SUNDIALS" not in out and "sundials" not in out
    assert "import_wrapper" in out and "export_wrapper" not in out and "fmi2_frontend" not in out


def test_patch_names_a_missing_text(tmp_path) -> None:
    with pytest.raises(ValueError, match="USE_SUNDIALS"):
        patch(SETUP.replace(EDITS[0][0], ""))
    f = tmp_path / "setup.py"
    f.write_text("nothing to patch\n")
    assert main([str(f)]) == 2 and f.read_text() == "nothing to patch\n"  # input left as it was
