"""Shared fixtures of the test suite: the built FMU, the paper's parameters; the ``slow`` marker."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from feeddrive.paper import paper_parameters

REPO = Path(__file__).resolve().parents[1]
FMU = REPO / "build" / "LinearMotorFeedDrive.fmu"
PKG_FMU = REPO / "python" / "feeddrive" / FMU.name     # the package's copy (make fmu), Plant's default


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", "slow: takes more than ~20 s (deselect with -m 'not slow')")


@pytest.fixture(scope="session")
def fmu_path() -> Path:
    """build/LinearMotorFeedDrive.fmu, built with `make fmu` when it or the package's copy is missing."""
    if not (FMU.is_file() and PKG_FMU.is_file()):
        subprocess.run(["make", "fmu"], cwd=REPO, check=True)
    assert FMU.is_file() and PKG_FMU.is_file(), f"`make fmu` did not produce {FMU} and {PKG_FMU}"
    return FMU


@pytest.fixture(scope="session")
def paper() -> dict[str, float | int | bool]:
    """Every FMU parameter at the paper's value (SI), from feeddrive.paper."""
    return paper_parameters()
