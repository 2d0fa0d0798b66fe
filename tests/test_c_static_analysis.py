"""GCC's static analyser (``-fanalyzer``) over every C source of the FMUs, compiled as the
Makefile builds them: the compiler commands of ``make fmu`` (dry run) give each shared
library's sources and flags (``-std``, ``-I``, ``-D``, ``-W``, ``-f``); every source is compiled
once per distinct flag set with ``-fanalyzer`` added, ``-Werror`` kept, and must give no
diagnostic but the known false positives below.  The source list so follows the Makefile,
whatever its variables are named.

The analysis runs at ``-O0`` in place of the build's ``-O3``: the optimiser folds away what
the analyser would follow (at ``-O3`` GCC 12 misses the planted double free and leak below);
the build itself keeps ``-O3``'s own warnings as errors.  The planted fault (a double free, a
leak, a NULL dereference) is compiled the same way: the analyser must report it, or the clean
result would mean nothing.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
#: a compiler flag kept from the build's command (the rest: -shared, -o, -l, -Wl, are the link's)
KEPT = ("-std=", "-I", "-D", "-W", "-f")
#: (function, check) of the analyser's known false positives, with the reason
FALSE_POSITIVES: dict[tuple[str, str], str] = {}

PLANTED = r"""
#include <stdlib.h>
int planted(int n) {
    int *p = malloc(sizeof *p);
    if (n > 0) { free(p); }
    free(p);                       /* double free when n > 0 */
    int *q = malloc(sizeof *q);
    *q = n;                        /* q may be NULL; leaked */
    return n;
}
"""


def _make_value(name: str) -> str:
    """The value of the Makefile's variable ``name`` (an extra rule read from stdin prints it)."""
    p = subprocess.run(
        ["make", "--no-print-directory", "-s", "-f", "Makefile", "-f", "-", f"print-{name}"],
        input="print-%:\n\t@echo '$($*)'\n",
        cwd=REPO,
        capture_output=True,
        text=True,
        check=True,
        timeout=60,
    )
    return p.stdout.strip()


def _gcc_with_analyser() -> str:
    gcc = shutil.which("gcc")
    if gcc is None:
        pytest.skip("gcc is not installed: -fanalyzer is GCC's")
    probe = subprocess.run(
        [gcc, "-fanalyzer", "-x", "c", "-c", "-", "-o", "/dev/null"],
        input="int x;\n",
        capture_output=True,
        text=True,
        timeout=60,
    )
    if probe.returncode != 0:
        pytest.skip(f"{gcc} has no -fanalyzer (GCC >= 10): {probe.stderr.strip()}")
    return gcc


def compile_units() -> list[tuple[str, tuple[str, ...]]]:
    """(source, flags) of every C source of every shared library ``make fmu`` links, once per
    distinct flag set, in build order."""
    cc = _make_value("CC")
    dry = subprocess.run(
        ["make", "--no-print-directory", "-n", "-B", "fmu"],
        cwd=REPO,
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    ).stdout.replace("\\\n", " ")
    units: dict[tuple[str, tuple[str, ...]], None] = {}
    for line in dry.splitlines():
        if not line.startswith(cc + " ") or " -shared" not in line:
            continue
        # the shell expands the arguments as make would run them ("$(cat build/fmi_include)")
        argv = subprocess.run(
            ["sh", "-c", "printf '%s\\n' " + line[len(cc) :]],
            cwd=REPO,
            capture_output=True,
            text=True,
            check=True,
            timeout=60,
        ).stdout.splitlines()
        flags: list[str] = []
        sources: list[str] = []
        args = iter(argv)
        for a in args:
            if a == "-o":
                next(args)
            elif a == "-I":
                flags += [a, next(args)]
            elif a.endswith(".c"):
                sources.append(a)
            elif a.startswith(KEPT) and not a.startswith("-Wl,"):
                flags.append(a)
        units.update(((s, tuple(flags)), None) for s in sources)
    return list(units)


def _analyse(gcc: str, source: str, flags: tuple[str, ...]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [gcc, *flags, "-O0", "-fanalyzer", "-c", source, "-o", "/dev/null"],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=600,
    )


def diagnostics(stderr: str) -> list[tuple[str, str, str]]:
    """(function, check, the diagnostic's line) of every warning or error in GCC's output."""
    out = []
    function = ""
    for line in stderr.splitlines():
        if m := re.match(r"\S+: In function [\u2018'](\w+)[\u2019']:", line):
            function = m.group(1)
        elif m := re.match(r"\S+:\d+:\d+: (?:warning|error): .*\[-W(?:error=)?([\w-]+)\]$", line):
            out.append((function, m.group(1), line))
        elif re.match(r"\S+:(\d+:\d+:)? (?:warning|error|fatal error): ", line):
            out.append((function, "", line))
    return out


def test_the_analyser_reports_a_planted_fault(tmp_path: Path) -> None:
    gcc = _gcc_with_analyser()
    src = tmp_path / "planted.c"
    src.write_text(PLANTED)
    proc = _analyse(gcc, str(src), ("-std=c99", "-Wall", "-Wextra", "-Werror"))
    assert proc.returncode != 0, "the analyser let a double free through"
    checks = {check for _, check, _ in diagnostics(proc.stderr)}
    assert {
        "analyzer-double-free",
        "analyzer-malloc-leak",
        "analyzer-possible-null-dereference",
    } <= checks, proc.stderr


@pytest.mark.slow
def test_fmu_sources_pass_the_static_analyser(fmu2_path: Path, fmu3_path: Path) -> None:
    """Every source of both FMUs (both FMI versions) as built: no analyser diagnostic."""
    gcc = _gcc_with_analyser()
    units = compile_units()
    sources = {s for s, _ in units}
    assert len(units) >= 4 and any(s.endswith("model_vars.c") for s in sources), units
    found, known = [], set()
    for source, flags in units:
        proc = _analyse(gcc, source, flags)
        diags = diagnostics(proc.stderr)
        new = [d for d in diags if d[:2] not in FALSE_POSITIVES]
        known.update(d[2] for d in diags if d[:2] in FALSE_POSITIVES)
        if new or (proc.returncode != 0 and not diags):
            found.append(f"{source} ({' '.join(flags)}):\n{proc.stderr.strip()}")
    print(
        f"{len(units)} compilations of {len(sources)} sources analysed; known false positives:",
        *sorted(known),
        sep="\n",
    )
    assert not found, "\n\n".join(found)
