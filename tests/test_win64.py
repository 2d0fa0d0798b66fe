"""The Windows x86-64 binaries the four FMUs carry (plant and controller, FMI 2.0 ``win64`` and
FMI 3.0 ``x86_64-windows``) run under Wine and compute what the Linux binaries compute.

One C host (tests/c/win_host.c) is built for Linux and, with mingw-w64, for Windows; each loads
the binaries of its platform taken out of the FMUs and runs: the plant and the controller in
closed loop for 1 s of co-simulation (FMI 2.0; FMI 2.0 from t = 1.2e6 s with a reference 2e10
samples long, whose sample counts pass 2^31 where a C long has 32 bits; FMI 3.0) and the
plant's model-exchange derivatives at three set states (FMI 2.0 and 3.0), and the messages of
calls the plant refuses (the same text). Both builds do the same IEEE double arithmetic from
the same sources, so the positions agree within 1e-12 m (a thousandth of the encoder's 1 nm
scale; the arithmetic leaves only last-bit differences of the C libraries' functions) and the
derivatives within 1e-12 relative.
Skipped, with the reason, where mingw-w64 or Wine is not installed (``make test`` installs both
where it can: root and apt-get). Wine's prefix is ~/.cache/feeddrive/wine (its first start
creates it, some 15 s; later runs take about 3 s).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
BUILD = REPO / "build"
OUT = BUILD / "tests_c"
MINGW_CC = os.environ.get("MINGW_CC", "x86_64-w64-mingw32-gcc")
# (FMU, Linux platform folder, Windows platform folder), in the host's argument order
FMUS = (
    ("LinearMotorFeedDrive.fmu", "linux64", "win64"),
    ("DriveController.fmu", "linux64", "win64"),
    ("LinearMotorFeedDrive3.fmu", "x86_64-linux", "x86_64-windows"),
    ("DriveController3.fmu", "x86_64-linux", "x86_64-windows"),
)
X_TOL = 1e-12  # [m]
DX_RTOL = 1e-12
STROKE_MIN = 0.015  # [m] the loop follows a 20 mm peak-to-peak sinusoid: it moved


def wine_program() -> str | None:
    """The Wine launcher: wine64 or wine on PATH, or Debian wine64's /usr/lib/wine/wine64."""
    for name in ("wine64", "wine"):
        if found := shutil.which(name):
            return found
    return "/usr/lib/wine/wine64" if os.access("/usr/lib/wine/wine64", os.X_OK) else None


def no_win64_reason() -> str | None:
    """Why the FMUs carry no Windows binary (build/win64/toolchain), or None."""
    note = BUILD / "win64" / "toolchain"
    text = note.read_text().strip() if note.is_file() else ""
    return (
        None
        if text.startswith("ok")
        else (text.partition(": ")[2] or "the FMUs were built without mingw-w64")
    )


def extract(fmu: Path, platform: str, dest: Path) -> Path:
    """The binary of ``platform`` in ``fmu``, copied out to dest/platform/."""
    with zipfile.ZipFile(fmu) as z:
        names = [
            n for n in z.namelist() if n.startswith(f"binaries/{platform}/") and not n.endswith("/")
        ]
        assert len(names) == 1, f"{fmu.name}: binaries/{platform}/ holds {names}"
        out = dest / platform / Path(names[0]).name
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_bytes(z.read(names[0]))
    return out


def parse(text: str) -> dict[str, list]:
    """The host's lines by tag: cs* k t x v u and me* s j x_j dx_j as numbers, msg2 status message
    as text."""
    rows: dict[str, list] = {}
    for line in text.splitlines():
        parts = line.rstrip("\r").split(" ", 1)
        if parts[0] == "msg2":
            rows.setdefault("msg2", []).append(parts[1])
        elif parts[0] and parts[0] != "done":
            rows.setdefault(parts[0], []).append([float(p) for p in parts[1].split()])
    return rows


@pytest.fixture(scope="module")
def fmus() -> list[Path]:
    paths = [BUILD / name for name, _, _ in FMUS]
    if not all(p.is_file() for p in paths):
        subprocess.run(["make", "fmu"], cwd=REPO, check=True)
    return paths


@pytest.fixture(scope="module")
def runs(
    fmus: list[Path], tmp_path_factory: pytest.TempPathFactory
) -> dict[str, dict[str, list[list[float]]]]:
    """The host's output on Linux and under Wine (the binaries out of the FMUs)."""
    if reason := no_win64_reason():
        pytest.skip(f"no win64 binaries: {reason}")
    if shutil.which(MINGW_CC) is None:
        pytest.skip(
            f"{MINGW_CC} (Debian gcc-mingw-w64-x86-64) is not installed: the Windows host cannot be built"
        )
    wine = wine_program()
    if wine is None:
        pytest.skip(
            "Wine (Debian wine64) is not installed: `make test` installs it where apt-get can"
        )
    subprocess.run(
        [
            "make",
            "-s",
            "-C",
            str(REPO / "tests" / "c"),
            f"MINGW_CC={MINGW_CC}",
            str(OUT / "win_host"),
            str(OUT / "win_host.exe"),
        ],
        check=True,
        capture_output=True,
        text=True,
    )
    d = tmp_path_factory.mktemp("win64")
    linux = [str(extract(f, lin, d / f.stem)) for f, (_, lin, _) in zip(fmus, FMUS, strict=True)]
    windows = [str(extract(f, win, d / f.stem)) for f, (_, _, win) in zip(fmus, FMUS, strict=True)]
    lin = subprocess.run(
        [str(OUT / "win_host"), *linux], capture_output=True, text=True, timeout=120
    )
    assert lin.returncode == 0, lin.stdout[-2000:] + lin.stderr[-2000:]
    prefix = Path(os.environ.get("WINEPREFIX", Path.home() / ".cache" / "feeddrive" / "wine"))
    prefix.parent.mkdir(parents=True, exist_ok=True)
    env = dict(
        os.environ,
        WINEPREFIX=str(prefix),
        WINEDEBUG="-all",
        WINEARCH="win64",
        WINEDLLOVERRIDES="mscoree,mshtml=",
    )  # no Mono or Gecko set-up on the prefix's first start
    win = subprocess.run(
        [wine, str(OUT / "win_host.exe"), *windows],
        capture_output=True,
        text=True,
        timeout=600,
        env=env,
    )
    assert win.returncode == 0 and "done" in win.stdout, (
        f"under Wine (exit {win.returncode}):\n{win.stdout[-2000:]}\n{win.stderr[-2000:]}"
    )
    return {"linux": parse(lin.stdout), "windows": parse(win.stdout)}


def test_every_fmu_carries_linux_and_windows_binaries(fmus: list[Path]) -> None:
    if reason := no_win64_reason():
        pytest.skip(f"no win64 binaries: {reason}")
    for fmu, (_, lin, win) in zip(fmus, FMUS, strict=True):
        names = zipfile.ZipFile(fmu).namelist()
        ident = fmu.stem
        assert f"binaries/{lin}/{ident}.so" in names and f"binaries/{win}/{ident}.dll" in names, (
            fmu.name,
            names,
        )


def test_dlls_import_only_the_c_runtime_and_export_only_their_fmi_functions(
    fmus: list[Path], tmp_path: Path
) -> None:
    if reason := no_win64_reason():
        pytest.skip(f"no win64 binaries: {reason}")
    objdump = MINGW_CC[: -len("gcc")] + "objdump"
    if shutil.which(objdump) is None:
        pytest.skip(f"{objdump} (Debian binutils-mingw-w64-x86-64) is not installed")
    for fmu, (_, _, win) in zip(fmus, FMUS, strict=True):
        text = subprocess.run(
            [objdump, "-p", str(extract(fmu, win, tmp_path / fmu.stem))],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        imports = {d.lower() for d in re.findall(r"DLL Name: (\S+)", text)}
        assert imports <= {"kernel32.dll", "msvcrt.dll", "ucrtbase.dll"} | {
            d for d in imports if d.startswith("api-ms-win-crt-")
        }, imports
        exports = re.findall(
            r"^\s*\[\s*\d+\]\s+(\S+)$", text.split("[Ordinal/Name Pointer] Table")[1], re.M
        )
        prefix = "fmi3" if win == "x86_64-windows" else "fmi2"
        assert exports and all(e.startswith(prefix) for e in exports), (fmu.name, exports)
        assert f"{prefix}Instantiate" in exports or f"{prefix}InstantiateCoSimulation" in exports
        assert len(exports) == (44 if prefix == "fmi2" else 75), (fmu.name, len(exports))


@pytest.mark.parametrize("tag", ["cs2", "cs2late", "cs3"])
def test_cosimulation_under_wine_equals_linux(runs: dict, tag: str) -> None:
    lin, win = runs["linux"][tag], runs["windows"][tag]
    assert len(lin) == len(win) == 101  # every 10 ms of 1 s
    assert [r[:2] for r in lin] == [r[:2] for r in win]  # the same samples and times
    dx = max(abs(a[2] - b[2]) for a, b in zip(lin, win, strict=True))
    assert dx <= X_TOL, f"{tag}: max |x_win64 - x_linux| = {dx:.3g} m"
    du = max(abs(a[4] - b[4]) for a, b in zip(lin, win, strict=True))
    assert du <= 1e-9, f"{tag}: max |u_win64 - u_linux| = {du:.3g} V"
    x = [r[2] for r in win]
    assert max(x) - min(x) >= STROKE_MIN, f"{tag}: the loop moved {max(x) - min(x):.4g} m only"


@pytest.mark.parametrize("tag", ["me2", "me3"])
def test_derivatives_under_wine_equal_linux(runs: dict, tag: str) -> None:
    lin, win = runs["linux"][tag], runs["windows"][tag]
    assert len(lin) == len(win) >= 3 * 9
    for a, b in zip(lin, win, strict=True):
        assert a[:3] == b[:3]  # state s, element j, value x_j
        assert abs(a[3] - b[3]) <= DX_RTOL * max(1.0, abs(a[3])), (tag, a, b)
    # der(x) = v at each set state (0, +0.05, -0.05 m/s): the call evaluated the state it was given
    assert [r[3] for r in win if r[1] == 0] == [r[2] for r in win if r[1] == 1]


def test_refusals_under_wine_say_what_linux_says(runs: dict) -> None:
    """Out-of-range values and a NULL category list: the same status and the same message, its
    numbers formatted as on Linux (C99 printf: 1e+30, inf, subnormals, %zu)."""
    lin, win = runs["linux"]["msg2"], runs["windows"]["msg2"]
    assert win == lin
    assert len(win) == 4 and all(m.startswith("3 ") for m in win)  # fmi2Error
    assert "m = 1e+30 is out of range: allowed [0.001, 10000] kg" in win[1]
    assert win[3].endswith("nCategories = 2")
