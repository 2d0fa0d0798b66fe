"""Shared fixtures of the test suite: the built FMUs (FMI 2.0 and FMI 3.0), the paper's
parameters; the ``slow`` marker."""

from __future__ import annotations

import os

# one BLAS thread per process, set before numpy is first imported: the suite runs one
# process per core, and OpenBLAS's own threads on the same cores spin while they wait
# (test_interval_coverage: 230 s of CPU with OpenBLAS's 2 threads, 115 s with 1)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

from feeddrive.model_description import FMU_ENV
from feeddrive.paper import paper_parameters
from session_cache import CACHE_ENV

REPO = Path(__file__).resolve().parents[1]
FMU = REPO / "build" / "LinearMotorFeedDrive.fmu"
PKG_FMU = REPO / "python" / "feeddrive" / FMU.name  # the package's copy (make fmu), Plant's default
FMU3 = REPO / "build" / "LinearMotorFeedDrive3.fmu"  # the same plant as FMI 3.0 (make fmu)
VERSIONS = ("2.0", "3.0")


#: test modules that exercise the plant's physics through feeddrive.fmu.Plant: each of their
#: tests that uses ``fmu_path`` runs on both FMUs (``[fmi2]``, ``[fmi3]``), except those marked
#: ``fmi2_only`` (FMI 2.0 specifics, or a slow test whose FMI 3.0 twin is a subset: see there)
BOTH_VERSIONS = {
    "test_fmu_breakaway",
    "test_fmu_compliance",
    "test_fmu_current_loop",
    "test_fmu_elements",
    "test_fmu_events",
    "test_fmu_friction_steady",
    "test_fmu_frictional_lag",
    "test_fmu_maps",
    "test_fmu_prerolling",
    "test_fmu_static_friction",
    "test_fmu_tolerance",
    "test_fmu_shared",
    "test_cs_agreement",
    "test_physics_effects",
    "test_position_friction",
    "test_cs_fast_path",
}

#: the 30 test modules of the longest summed test time (setup included), the longest first
#: (CPU time of each test's process and children on 2 workers, which a shared machine's load
#: does not stretch: these are 90 % of the suite's): handed out first, so that none of them is
#: left running alone at the end while the other worker idles (xdist's own order, by number
#: of tests, puts a one-test file of minutes last)
HEAVY_FIRST = (
    "test_interval_coverage",
    "test_diagnose_hidden",
    "test_diagnose_noise_floor",
    "test_diagnose_compliance_band",
    "test_plan",
    "test_diagnose_honest",
    "test_identify_bootstrap",
    "test_identify_roundtrip",
    "test_cs_hardening",
    "test_c_fuzz_coverage",
    "test_diagnose_verdict",
    "test_c_state_and_limits",
    "test_diagnose",
    "test_package_install",
    "test_c_controller",
    "test_cs_fast_path",
    "test_study",
    "test_cs_agreement",
    "test_diagnose_compliance",
    "test_fmu_friction_steady",
    "test_docs",
    "test_identify_parametric",
    "test_c_fmi3",
    "test_c_static_analysis",
    "test_reports_browser",
    "test_harness",
    "test_diagnose_start",
    "test_systems",
    "test_diagnose_emps",
    "test_experiments",
)


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", "slow: takes more than ~20 s (deselect with -m 'not slow')")
    config.addinivalue_line("markers", "fmi2_only: in a BOTH_VERSIONS module, run on FMI 2.0 only")


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Put the files of HEAVY_FIRST first, in that order (the rest keep theirs): `make test`
    runs ``--dist loadfile --no-loadscope-reorder``, which hands the files out in this order."""
    rank = {name: i for i, name in enumerate(HEAVY_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.stem, len(rank)))


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    """Parametrise ``fmi`` (and so ``fmu_path``) over both versions in BOTH_VERSIONS modules."""
    if (
        metafunc.module.__name__.rpartition(".")[2] in BOTH_VERSIONS
        and "fmi" in metafunc.fixturenames
    ):
        versions = VERSIONS[:1] if metafunc.definition.get_closest_marker("fmi2_only") else VERSIONS
        metafunc.parametrize("fmi", versions, ids=lambda v: f"fmi{v[0]}", scope="module")


@pytest.fixture(scope="session")
def fmu2_path() -> Path:
    """build/LinearMotorFeedDrive.fmu, built with `make fmu` when it or the package's copy is missing."""
    if not (FMU.is_file() and PKG_FMU.is_file()):
        subprocess.run(["make", "fmu"], cwd=REPO, check=True)
    assert FMU.is_file() and PKG_FMU.is_file(), f"`make fmu` did not produce {FMU} and {PKG_FMU}"
    return FMU


@pytest.fixture(scope="session")
def fmu3_path(fmu2_path: Path) -> Path:
    """build/LinearMotorFeedDrive3.fmu (built by the same `make fmu`)."""
    if not FMU3.is_file():
        subprocess.run(["make", "fmu"], cwd=REPO, check=True)
    assert FMU3.is_file(), f"`make fmu` did not produce {FMU3}"
    return FMU3


@pytest.fixture(scope="session")
def fmi() -> str:
    """The FMI version of ``fmu_path``: "2.0", or each of VERSIONS in BOTH_VERSIONS modules."""
    return VERSIONS[0]


@pytest.fixture(scope="module")
def fmu_path(fmi: str, fmu2_path: Path, fmu3_path: Path) -> Iterator[Path]:
    """The plant FMU of version ``fmi``: build/LinearMotorFeedDrive.fmu (FMI 2.0), or
    build/LinearMotorFeedDrive3.fmu, which ``$FEEDDRIVE_FMU`` then names for the module's
    tests (a ``Plant()`` without a path loads it)."""
    if fmi == "2.0":
        yield fmu2_path
        return
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv(FMU_ENV, str(fmu3_path))
        yield fmu3_path


@pytest.fixture(scope="session", params=VERSIONS, ids=lambda v: f"fmi{v[0]}")
def fmu_version(
    request: pytest.FixtureRequest, fmu2_path: Path, fmu3_path: Path
) -> tuple[Path, str]:
    """(path, FMI version) of each build of the plant: the tests that take it run on both."""
    return (fmu2_path if request.param == "2.0" else fmu3_path), request.param


@pytest.fixture(scope="session")
def paper() -> dict[str, float | int | bool]:
    """Every FMU parameter at the paper's value (SI), from feeddrive.paper."""
    return paper_parameters()


@pytest.fixture(scope="session", autouse=True)
def _session_cache(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """The directory of session_cache's results: the session's base temporary directory,
    the one the xdist workers share (the parent of each worker's own)."""
    base = tmp_path_factory.getbasetemp()
    root = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "session_cache"
    root.mkdir(exist_ok=True)
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv(CACHE_ENV, str(root))
        yield root
