#!/usr/bin/env python3
"""Zip modelDescription.xml, the shared libraries (one per platform) and the C sources into an FMU."""

from __future__ import annotations

import argparse
import zipfile
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--xml", required=True)
    ap.add_argument("--so", required=True)
    ap.add_argument(
        "--sources",
        nargs="+",
        required=True,
        help="folders whose *.c/*.h (or single files) go to sources/",
    )
    ap.add_argument("--out", required=True)
    ap.add_argument(
        "--platform",
        default="linux64",
        help="binaries/ folder of --so: linux64 (FMI 2.0), x86_64-linux (FMI 3.0)",
    )
    ap.add_argument(
        "--binary",
        nargs=2,
        action="append",
        default=[],
        metavar=("PLATFORM", "FILE"),
        help="a further binary and its binaries/ folder, e.g. win64 X.dll (FMI 2.0), "
        "x86_64-windows X.dll (FMI 3.0); repeatable",
    )
    a = ap.parse_args()
    binaries = [(a.platform, Path(a.so))] + [(plat, Path(f)) for plat, f in a.binary]
    platforms = [plat for plat, _ in binaries]
    if len(set(platforms)) != len(platforms):
        ap.error(f"--binary: a platform is given twice ({', '.join(platforms)})")
    out = Path(a.out)
    tmp = out.with_suffix(".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        z.write(a.xml, "modelDescription.xml")
        for plat, lib in binaries:
            z.write(lib, f"binaries/{plat}/{lib.name}")
        for folder in map(Path, a.sources):
            for f in [folder] if folder.is_file() else sorted(folder.glob("*.[ch]")):
                z.write(f, f"sources/{f.name}")
    tmp.replace(out)
    print(f"wrote {out} ({', '.join(platforms)})")


if __name__ == "__main__":
    main()
