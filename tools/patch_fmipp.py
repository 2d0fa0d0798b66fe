"""Patch the setup.py of fmipp's PyPI sdist (FMI++ 2.1.0) so that it builds here (make importers).

* Without SUNDIALS: its CVODE stepper is written for SUNDIALS 2.x (CVodeCreate(CV_BDF,
  CV_NEWTON)); Debian has 6.x.  The model-exchange steppers left are boost::odeint's (the
  default without SUNDIALS is Dormand-Prince 5 with step control, ``integratorDP``).
* Only the import module (``fmipp.fmippim``): the FMU-export front-ends are not needed to
  import an FMU, and skipping them halves the compile.

Every replaced text must be found exactly once, so a changed sdist stops the build with the
text that is missing.  Usage: python tools/patch_fmipp.py path/to/setup.py
"""

from __future__ import annotations

import sys
from pathlib import Path

EDITS = (
    ("    ( 'USE_SUNDIALS', None ),\n", ""),
    (", '-DUSE_SUNDIALS' ]", " ]"),
    ("    '-lsundials_cvode',\n    '-lsundials_nvecserial'\n", ""),
    (
        "      import_wrapper,\n      export_wrapper,\n      fmi2_frontend,\n      fmi1_frontend_lib\n",
        "      import_wrapper,\n",
    ),
)


def patch(text: str) -> str:
    """``text`` with every edit of EDITS applied; ValueError naming an edit not found once."""
    for old, new in EDITS:
        if text.count(old) != 1:
            raise ValueError(
                f"fmipp setup.py: expected once, found {text.count(old)} times: {old!r}"
            )
        text = text.replace(old, new)
    return text


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print("usage: patch_fmipp.py SETUP_PY", file=sys.stderr)
        return 2
    path = Path(argv[0])
    try:
        path.write_text(patch(path.read_text()))
    except (OSError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
