"""The closed loop as system files (SSP 1.0, OSP, fmpy container FMU) run by existing engines,
against the Python harness's two-FMU run (:func:`~feeddrive.harness.two_fmus.simulate_two_fmus`,
bitwise the harness's Python-controller run, tests/test_controller_fmu.py).

Conventions.  Harness: macro step Ts, u(t_k) from x(t_k) (no delay beyond the current
loop's own sample, Eq. 2).  fmpy's container FMU: the same (its components step in order and
the controller's input is set before its output is read): agreement asked 0.01 um.
libcosim's fixed-step algorithm and fmpy's ``simulate_ssp``: Jacobi, outputs transferred
after the step, so u(t_k) comes from x(t_k - h), one macro step h late.  With h = Ts the
state-space design (current estimator, no delay margin for a whole extra sample) is unstable:
the OSP structure steps at h = Ts/10.  Equal conventions: libcosim against the same Jacobi
master stepped from Python (feeddrive.systems.jacobi), 0.01 um, without the scale's
quantisation (with it a last-bit difference of x -- libcosim's time is integer nanoseconds --
flips a 100 nm level and grows to micrometres).  Against the harness the delay h acts as a
measurement error v h that the loop passes on: measured 6.9 um at h = 50 us, halving with h
(3.3 um at 25 us, 1.6 um at 12.5 us), ~0.14 um per us of delay.
"""

from __future__ import annotations

import zipfile
from xml.etree import ElementTree as ET

import numpy as np
import pytest
from fmpy.ssp.ssd import read_ssd, read_ssv

from feeddrive.harness.two_fmus import simulate_two_fmus
from feeddrive.systems import (
    run_container,
    run_fmpy_ssp,
    run_libcosim_osp,
    sec3_system,
    sec4_system,
    write_all,
)
from feeddrive.systems.jacobi import simulate_jacobi

TOL_EQUAL = 1e-8  #: 0.01 um, equal conventions
libcosim = pytest.importorskip("libcosimpy", reason="libcosimpy: python/pyproject.toml [test]")


@pytest.fixture(scope="module")
def sec3(fmu_path, tmp_path_factory):
    s = sec3_system()
    files = write_all(s, tmp_path_factory.mktemp("sys"))
    ref = simulate_two_fmus(s.plant, s.controller, s.n, s.x0)
    return s, files, ref


def test_files_are_standard_form(sec3) -> None:
    """The SSD validates against SSP 1.0's schema (fmpy's read_ssd), the .ssv files against
    theirs, with every start value; the OSP file names both simulators and connections."""
    s, files, _ = sec3
    ssd = read_ssd(str(files["ssp"]))  # validates
    names = {c.name for c in ssd.system.elements}
    assert names == {"plant", "controller"}
    assert {
        (c.startElement, c.startConnector, c.endElement, c.endConnector)
        for c in ssd.system.connections
    } == {("plant", "x", "controller", "x_meas"), ("controller", "u", "plant", "u")}
    sv = s.start_values()
    for comp in ("plant", "controller"):
        ps = read_ssv(str(files["ssp"]), resource=f"resources/{comp}.ssv")  # validates
        assert {p.name for p in ps.parameters} == set(sv[comp])
    with zipfile.ZipFile(files["ssp"]) as z:
        assert {"resources/LinearMotorFeedDrive.fmu", "resources/DriveController.fmu"} <= set(
            z.namelist()
        )
    root = ET.parse(files["osp"]).getroot()
    ns = {"o": "http://opensimulationplatform.com/MSMI/OSPSystemStructure"}
    assert {e.get("name") for e in root.findall("o:Simulators/o:Simulator", ns)} == {
        "plant",
        "controller",
    }
    assert len(root.findall("o:Connections/o:VariableConnection", ns)) == 2
    assert float(root.find("o:BaseStepSize", ns).text) == pytest.approx(s.Ts / 10)


def test_container_fmu_is_the_harness_run(sec3) -> None:
    """Sec. 3 in fmpy's container FMU (simulate_fmu, step Ts): the harness's convention, so
    the harness's run to 0.01 um (bitwise here)."""
    s, files, ref = sec3
    r = run_container(files["container"], s.n, s.Ts)
    assert float(np.max(np.abs(r["x"] - ref["x"]))) <= TOL_EQUAL
    assert float(np.max(np.abs(r["u"][:-1] - ref["u"][:-1]))) <= 1e-12  # ref holds u[n] = u[n-1]


def test_sec4_gms_container_is_the_harness_run(fmu_path, tmp_path) -> None:
    """One Sec. 4 case (GMS feedforward on the nominal model, perturbed plant, 12.5 s)."""
    s = sec4_system("gms")
    files = write_all(s, tmp_path)
    ref = simulate_two_fmus(s.plant, s.controller, s.n, s.x0)
    r = run_container(files["container"], s.n, s.Ts)
    assert float(np.max(np.abs(r["x"] - ref["x"]))) <= TOL_EQUAL


@pytest.mark.slow
def test_libcosim_osp_equal_convention_and_delay(fmu_path, tmp_path) -> None:
    """libcosim on the OSP structure (h = Ts/10): without quantisation the Python Jacobi
    master's run to 0.01 um; against the harness the one-macro-step delay, ~0.14 um per us:
    7 um at 50 us, asked <= 10 um (and > 1 um, so that the delay is what is measured)."""
    s = sec3_system()
    s.controller["scale.quantum"] = 0.0
    files = write_all(s, tmp_path)
    r = run_libcosim_osp(files["osp"].parent, s.n, s.Ts, substeps=10)
    j = simulate_jacobi(s)
    assert float(np.nanmax(np.abs(r["x"][1:] - j["x"][1:]))) <= TOL_EQUAL
    h = simulate_two_fmus(s.plant, s.controller, s.n, s.x0)
    d = float(np.nanmax(np.abs(r["x"][1:] - h["x"][1:])))
    assert 1e-6 < d <= 10e-6


@pytest.mark.slow
def test_libcosim_osp_sec3_with_quantisation(sec3) -> None:
    """The Sec. 3 run itself (100 nm scale) in libcosim: within 10 um of the harness's
    (delay 50 us plus quantisation-level flips; measured 7.8 um)."""
    s, files, ref = sec3
    r = run_libcosim_osp(files["osp"].parent, s.n, s.Ts, substeps=10)
    assert float(np.nanmax(np.abs(r["x"][1:] - ref["x"][1:]))) <= 10e-6


def test_fmpy_simulate_ssp_runs_our_package(sec3) -> None:
    """fmpy's simulate_ssp loads, validates and runs the package with its parameter sets
    (x(Ts) is the plant's first step from x0, not from the FMU's default 0.15 m), but starts
    every connector at 0.0: the first macro step gives the controller x_meas = 0, a 0.12 m
    error that saturates u, so its run is not the harness's (measured: mm).  Documented, not
    a convention we can match."""
    s, files, _ref = sec3
    s10 = 10
    r = run_fmpy_ssp(files["ssp"], 200, s.Ts, substeps=s10)
    assert abs(r["x"][1] - s.x0) < 1e-6
    assert abs(r["u"][1]) == pytest.approx(s.controller["u_limit"])
