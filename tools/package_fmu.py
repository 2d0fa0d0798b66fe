#!/usr/bin/env python3
"""Zip modelDescription.xml, the shared library and the C sources into an FMU."""
from __future__ import annotations

import argparse
import zipfile
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--xml", required=True)
    ap.add_argument("--so", required=True)
    ap.add_argument("--sources", nargs="+", required=True, help="folders whose *.c/*.h (or single files) go to sources/")
    ap.add_argument("--out", required=True)
    ap.add_argument("--platform", default="linux64",
                    help="binaries/ folder: linux64 (FMI 2.0), x86_64-linux (FMI 3.0)")
    a = ap.parse_args()
    so = Path(a.so)
    out = Path(a.out)
    tmp = out.with_suffix(".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        z.write(a.xml, "modelDescription.xml")
        z.write(so, f"binaries/{a.platform}/{so.name}")
        for folder in map(Path, a.sources):
            for f in [folder] if folder.is_file() else sorted(folder.glob("*.[ch]")):
                z.write(f, f"sources/{f.name}")
    tmp.replace(out)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
