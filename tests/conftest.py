"""Shared fixtures of the test suite: the built FMUs (FMI 2.0 and FMI 3.0), the paper's
parameters; the ``slow`` marker."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from feeddrive.paper import paper_parameters

REPO = Path(__file__).resolve().parents[1]
FMU = REPO / "build" / "LinearMotorFeedDrive.fmu"
PKG_FMU = REPO / "python" / "feeddrive" / FMU.name     # the package's copy (make fmu), Plant's default
FMU3 = REPO / "build" / "LinearMotorFeedDrive3.fmu"    # the same plant as FMI 3.0 (make fmu)
VERSIONS = ("2.0", "3.0")


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
def fmu3_path(fmu_path: Path) -> Path:
    """build/LinearMotorFeedDrive3.fmu (built by the same `make fmu`)."""
    if not FMU3.is_file():
        subprocess.run(["make", "fmu"], cwd=REPO, check=True)
    assert FMU3.is_file(), f"`make fmu` did not produce {FMU3}"
    return FMU3


@pytest.fixture(scope="session", params=VERSIONS, ids=lambda v: f"fmi{v[0]}")
def fmu_version(request: pytest.FixtureRequest, fmu_path: Path, fmu3_path: Path) -> tuple[Path, str]:
    """(path, FMI version) of each build of the plant: the tests that take it run on both."""
    return (fmu_path if request.param == "2.0" else fmu3_path), request.param


@pytest.fixture(scope="session")
def paper() -> dict[str, float | int | bool]:
    """Every FMU parameter at the paper's value (SI), from feeddrive.paper."""
    return paper_parameters()
