#!/usr/bin/env python3
"""Cross-build one FMU's Windows x86-64 DLL with mingw-w64 and check what it imports and exports.

The sources are compiled to objects, their export directives (``.drectve``: the FMI headers mark
every FMI function ``__declspec(dllexport)`` under ``_WIN32``) are dropped, and the DLL exports
exactly the functions named ``<prefix>[A-Z]...`` that the objects define, through a module
definition file: an FMI 3.0 DLL, whose FMI 2.0 glue is compiled in, exports only ``fmi3*`` (the
version script of the Linux build does the same). The DLL must import from the Windows C
runtime and KERNEL32 only.

Usage: win_dll.py --cc x86_64-w64-mingw32-gcc --out X.dll --exports fmi2 -- CFLAGS... SOURCES...
(arguments after ``--`` ending in ``.c`` are sources, the others compiler flags).
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
from pathlib import Path

# what a DLL of the FMUs may import: the Windows C runtime (msvcrt or the UCRT's api sets) and
# KERNEL32 (which the C runtime start-up code of every DLL needs)
ALLOWED_IMPORTS = re.compile(
    r"^(kernel32\.dll|msvcrt\.dll|ucrtbase\.dll|api-ms-win-crt-[a-z0-9-]+\.dll)$", re.I
)


def tool(cc: str, name: str) -> str:
    """The binutils program ``name`` beside the cross compiler ``cc`` (same target prefix)."""
    return cc[: -len("gcc")] + name if cc.endswith("gcc") else name


def run(cmd: list[str], cwd: Path | None = None) -> str:
    """Run cmd; on failure print its output and exit with its status."""
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.stderr.write(r.stdout + r.stderr)
        sys.exit(f"error: {cmd[0]} failed (exit {r.returncode})")
    return r.stdout


def pe_imports_exports(objdump: str, dll: Path) -> tuple[list[str], list[str]]:
    """The DLL names a PE file imports from and the names it exports (objdump -p)."""
    text = run([objdump, "-p", str(dll)])
    imports = re.findall(r"^\s*DLL Name: (\S+)", text, re.M)
    exports: list[str] = []
    table = text.split("[Ordinal/Name Pointer] Table", 1)
    if len(table) == 2:
        for line in table[1].splitlines()[1:]:
            m = re.match(r"^\s*\[\s*\d+\]\s+(\S+)", line)
            if not m:
                break
            exports.append(m.group(1))
    return imports, exports


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--cc", default="x86_64-w64-mingw32-gcc")
    ap.add_argument("--out", required=True, type=Path)
    ap.add_argument(
        "--exports", required=True, help="prefix of the exported functions: fmi2 or fmi3"
    )
    ap.add_argument("rest", nargs=argparse.REMAINDER, help="-- compiler flags and sources")
    a = ap.parse_args()
    rest = a.rest[1:] if a.rest[:1] == ["--"] else a.rest
    sources = [Path(s).resolve() for s in rest if s.endswith(".c")]
    flags: list[str] = []
    for s in rest:  # include folders made absolute: the compiler runs in a scratch folder
        if s.endswith(".c"):
            continue
        if flags and flags[-1] == "-I":
            flags[-1] = f"-I{Path(s).resolve()}"
        elif s.startswith("-I") and len(s) > 2:
            flags.append(f"-I{Path(s[2:]).resolve()}")
        else:
            flags.append(s)
    if not sources:
        sys.exit("error: win_dll.py: no .c sources given")
    names = [s.stem for s in sources]
    if len(set(names)) != len(names):
        sys.exit("error: win_dll.py: two sources share a file name")
    nm, objcopy, objdump = tool(a.cc, "nm"), tool(a.cc, "objcopy"), tool(a.cc, "objdump")
    a.out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=a.out.parent) as tmp:
        work = Path(tmp)
        run([a.cc, *flags, "-c", *map(str, sources)], cwd=work)
        objs = [work / f"{n}.o" for n in names]
        for o in objs:
            run([objcopy, "--remove-section", ".drectve", str(o)])
        pat = re.compile(rf"^{re.escape(a.exports)}[A-Z]\w*$")
        syms = sorted(
            {
                parts[2]
                for line in run([nm, "-g", "--defined-only", *map(str, objs)]).splitlines()
                if len(parts := line.split()) == 3 and parts[1] == "T" and pat.match(parts[2])
            }
        )
        if not syms:
            sys.exit(f"error: win_dll.py: the sources define no {a.exports}* function")
        deffile = work / "exports.def"
        deffile.write_text("EXPORTS\n" + "".join(f"    {s}\n" for s in syms))
        tmp_dll = work / a.out.name
        run(
            [
                a.cc,
                "-shared",
                "-static-libgcc",
                "-s",
                "-Wl,--no-undefined",
                "-o",
                str(tmp_dll),
                *map(str, objs),
                str(deffile),
                "-lm",
            ]
        )
        imports, exports = pe_imports_exports(objdump, tmp_dll)
        bad = [d for d in imports if not ALLOWED_IMPORTS.match(d)]
        if bad:
            sys.exit(
                f"error: {a.out} imports {', '.join(bad)}: allowed only KERNEL32 and the C runtime"
            )
        if sorted(exports) != syms:
            sys.exit(
                f"error: {a.out} exports {len(exports)} names, expected the {len(syms)} {a.exports}* functions"
            )
        tmp_dll.replace(a.out)
    print(
        f"wrote {a.out} ({a.out.stat().st_size} bytes; imports {', '.join(imports)}; "
        f"{len(syms)} {a.exports}* exports)"
    )


if __name__ == "__main__":
    main()
