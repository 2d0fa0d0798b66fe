"""The package outside the checkout: a wheel built from python/ (the FMU as package data),
installed into a fresh venv in tmp_path (dependencies from PyPI or pip's cache), runs
`feeddrive run` from a working directory outside the checkout; without an FMU it stops with
one line naming where it looked (exit 2, no traceback)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import venv
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
FMU_NAME = "LinearMotorFeedDrive.fmu"

pytestmark = pytest.mark.slow


def _env(**extra: str) -> dict[str, str]:
    """The environment of a user of the installed package: nothing pointing into the checkout."""
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ("PYTHONPATH", "VIRTUAL_ENV", "FEEDDRIVE_FMU", "FEEDDRIVE_SHARED")
    }
    env.update(extra)
    return env


def _run(
    args: list[str], cwd: Path, env: dict[str, str], timeout: float
) -> subprocess.CompletedProcess:
    return subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def installed(tmp_path_factory, fmu_path: Path) -> tuple[Path, Path]:
    """(venv, site FMU): the wheel of a copy of python/ with the FMU, pip-installed into a new venv."""
    tmp = tmp_path_factory.mktemp("pkg")
    src = tmp / "python"
    shutil.copytree(
        REPO / "python",
        src,
        ignore=shutil.ignore_patterns("__pycache__", "*.egg-info", "build", FMU_NAME),
    )
    shutil.copy2(fmu_path, src / "feeddrive" / FMU_NAME)
    wheels = tmp / "wheels"
    p = _run(
        [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(wheels), str(src)],
        tmp,
        _env(),
        600,
    )
    assert p.returncode == 0, p.stdout + p.stderr
    (wheel,) = wheels.glob("feeddrive-*.whl")
    env_dir = tmp / "venv"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    # --no-compile: no bytecode for the thousands of modules of the dependencies (scipy,
    # pyarrow, dask, ...); the few that `feeddrive run` imports are compiled when imported
    p = _run(
        [str(env_dir / "bin" / "python"), "-m", "pip", "install", "-q", "--no-compile", str(wheel)],
        tmp,
        _env(),
        900,
    )
    assert p.returncode == 0, p.stdout + p.stderr
    site_fmu = Path(
        _run(
            [
                str(env_dir / "bin" / "python"),
                "-c",
                "import feeddrive.fmu as f; print(f.DEFAULT_FMU)",
            ],
            tmp,
            _env(),
            60,
        ).stdout.strip()
    )
    return env_dir, site_fmu


def test_wheel_carries_the_fmu_outside_the_checkout(installed):
    env_dir, site_fmu = installed
    assert env_dir in site_fmu.parents and REPO not in site_fmu.parents
    assert site_fmu.stat().st_size > 10_000


def test_installed_feeddrive_run_prints_the_tables_and_writes_the_report(installed, tmp_path):
    env_dir, _ = installed
    p = _run([str(env_dir / "bin" / "feeddrive"), "run", "--out", "report"], tmp_path, _env(), 900)
    assert p.returncode == 0, p.stdout + p.stderr
    for heading in ("Sec. 3", "Sec. 4", "GMS feedforward", "full model"):
        assert heading in p.stdout, heading
    assert "ODrive real-data section skipped: no shared data folder given" in p.stdout
    html = (tmp_path / "report" / "index.html").read_text()
    assert "fig16_feedforward.png" in html and "<table>" in html
    assert (tmp_path / "report" / "fig14_top_reversal.png").stat().st_size > 10_000


def test_installed_feeddrive_without_an_fmu_says_where_it_looked(installed, tmp_path):
    env_dir, site_fmu = installed
    exe = str(env_dir / "bin" / "feeddrive")
    nowhere = tmp_path / "nowhere.fmu"
    p = _run([exe, "run", "--out", "report"], tmp_path, _env(FEEDDRIVE_FMU=str(nowhere)), 120)
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert p.stderr.strip() == (
        f"feeddrive run: FEEDDRIVE_FMU={nowhere}: no FMU there (the package's "
        f"own copy, used when FEEDDRIVE_FMU is unset, would be {site_fmu})"
    )
    hidden = site_fmu.with_suffix(".hidden")
    site_fmu.rename(hidden)
    try:
        p = _run([exe, "run", "--out", "report"], tmp_path, _env(), 120)
    finally:
        hidden.rename(site_fmu)
    assert p.returncode == 2 and "Traceback" not in p.stderr
    line = p.stderr.strip()
    assert "\n" not in line and str(site_fmu) in line and "FEEDDRIVE_FMU is not set" in line
    assert not (tmp_path / "report" / "index.html").exists()
