"""The controller's computation delay (spec ``delay``, the controller FMU's ``ctrl.delay``) and
the masters that run the loop at h = Ts.

Harness with ``delay`` 1: the sample at t_k (its reference) runs on the measurement of
t_k-1, so what the controller computed from x_k acts over [t_k+1, t_k+2).  Our Gauss-Seidel
master (plant first, controller second) with the FMU's ``ctrl.delay`` = the spec's delay is
the harness run to the bit; a Jacobi master at h = Ts (the engines' convention: outputs
handed over after the step) with ``ctrl.delay`` 0 is the harness run with delay 1 -- the
handover is the delay -- to <= 1e-9 m without the scale's quantisation (the Jacobi clock,
integer nanoseconds, differs from k Ts in the last bit).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from c_build import make_c
from feeddrive.control.design_model import design_model
from feeddrive.control.margins import poor_margins
from feeddrive.fmu import Plant
from feeddrive.harness import simulate_closed_loop, sinusoid, state_space_spec
from feeddrive.harness.controller_fmu import controller_fmu_parameters, sinusoid_source
from feeddrive.harness.controllers import (
    PoorMarginsWarning,
    delay_margins,
    make_controller,
    pid_lead_spec,
    pid_spec,
)
from feeddrive.harness.two_fmus import simulate_two_fmus
from feeddrive.paper import paper_parameters
from feeddrive.systems.closed_loop import sec3_system
from feeddrive.systems.jacobi import simulate_jacobi

A, P, C = 0.030, 6.0, 0.150  #: the Sec. 3 sinusoid [m], [s], [m]


def _harness(spec: dict, duration: float, quantum: float = 1e-7):
    ref = sinusoid(A, P, C, duration)
    with Plant(paper_parameters(), interface="cs") as plant:
        return ref, simulate_closed_loop(
            plant, make_controller(spec, ref), ref.n, float(ref.x[0]), quantum=quantum
        )


def test_delay_zero_is_the_spec_without_it(fmu_path) -> None:
    """``delay`` 0 is the default to the bit; ``delay`` 1 changes the run (by the lag of one
    sample at the sinusoid's speed, well below a millimetre)."""
    spec = state_space_spec()
    _, r0 = _harness(spec, 0.3)
    _, r0b = _harness({**spec, "delay": 0}, 0.3)
    _, r1 = _harness({**spec, "delay": 1}, 0.3)
    assert np.array_equal(r0["x"], r0b["x"]) and np.array_equal(r0["u"], r0b["u"])
    d = float(np.max(np.abs(r1["x"] - r0["x"])))
    assert 1e-8 < d < 1e-4


@pytest.mark.parametrize("delay", [0, 1])
def test_gauss_seidel_master_is_the_harness_bit_for_bit(fmu_path, delay: int) -> None:
    """The 6 s Sec. 3 loop (100 nm scale), plant first then controller, macro step Ts, no
    set-then-get at one instant: the harness's run with the same delay, to the bit."""
    spec = {**state_space_spec(), "delay": delay}
    ref, h = _harness(spec, P)
    values = controller_fmu_parameters(spec, reference=sinusoid_source(A, P, C, P), quantum=1e-7)
    assert values.get("ctrl.delay", 0) == delay
    two = simulate_two_fmus(paper_parameters(), values, ref.n, float(ref.x[0]))
    assert np.array_equal(two["x"], h["x_measured"])
    assert np.array_equal(two["u"], h["u"])


def test_jacobi_at_ts_is_the_harness_with_delay_one(fmu_path) -> None:
    """The Jacobi master at h = Ts with ``ctrl.delay`` 0 (the system's Jacobi convention):
    the harness with delay 1 to <= 1e-9 m over the 6 s loop, without quantisation."""
    s = sec3_system(delay=1)
    assert s.jacobi_substeps == 1 and s.start_values(jacobi=True)["controller"]["ctrl.delay"] == 0
    s.controller["scale.quantum"] = 0.0
    j = simulate_jacobi(s)
    _, h = _harness({**state_space_spec(), "delay": 1}, P, quantum=0.0)
    assert float(np.max(np.abs(j["x"] - h["x"]))) <= 1e-9
    assert float(np.max(np.abs(j["u"][:-1] - h["u"][:-1]))) <= 1e-6


def test_delay_one_design_tracks_and_the_blind_design_loses_margin() -> None:
    """The state-space design placed on the model with the delay keeps GM > 6 dB, PM > 30 deg
    on the delayed loop; the PID's margins with the delay are computed on it and reported
    poor (the default PID: PM 28 -> 22 deg, one sample = 5.2 deg at its 29 Hz crossover)."""
    ref = sinusoid(A, P, C, 0.1)
    ss = make_controller({**state_space_spec(), "delay": 1}, ref)
    m = delay_margins({"delay": 1}, ss)
    assert m.gain_margin_db > 6 and m.phase_margin_deg > 30 and not poor_margins(m)
    pid0 = make_controller(pid_spec(), ref)
    m0 = pid0.margins(design_model(paper_parameters()))
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        make_controller({**pid_spec(), "delay": 1}, ref)
    m1 = pid0.margins(design_model(paper_parameters(), delay=1))
    # one sample of delay costs 360 f Ts degrees at the crossover
    assert m0.phase_margin_deg - m1.phase_margin_deg == pytest.approx(
        360 * m1.crossover_hz * 5e-4, abs=1.0
    )
    assert any(
        issubclass(x.category, PoorMarginsWarning) and "phase margin" in str(x.message) for x in w
    )


def test_bad_delay_refused() -> None:
    ref = sinusoid(A, P, C, 0.1)
    for bad in (2, -1, 0.5, True, "1"):
        with pytest.raises(ValueError, match="delay"):
            make_controller({**pid_lead_spec(), "delay": bad}, ref)


@pytest.fixture(scope="module")
def delay1_files(fmu_path, tmp_path_factory):
    """The Sec. 3 system with delay 1, no quantisation, written in its three forms, and the
    harness run it reproduces."""
    from feeddrive.systems import write_all

    s = sec3_system(delay=1)
    s.controller["scale.quantum"] = 0.0
    files = write_all(s, tmp_path_factory.mktemp("sys_delay1"))
    _, h = _harness({**state_space_spec(), "delay": 1}, P, quantum=0.0)
    return s, files, h


def test_system_files_say_their_convention(delay1_files) -> None:
    """The SSD runs libcosim's fixed step on the calling thread at h = Ts and names the
    convention; the OSP file says it; the Jacobi files carry ctrl.delay 0, the container 1."""
    import zipfile
    from xml.etree import ElementTree as ET

    s, files, _ = delay1_files
    with zipfile.ZipFile(files["ssp"]) as z:
        ssd = ET.fromstring(z.read("SystemStructure.ssd"))
        ssv = z.read("resources/controller.ssv").decode()
    alg = ssd.find(".//{http://opensimulationplatform.com/SSP/OSPAnnotations}FixedStepAlgorithm")
    assert alg.get("numWorkerThreads") == "0" and float(alg.get("baseStepSize")) == s.Ts
    conv = ssd.find(".//{https://feeddrive.invalid/ssp/delay}Delay")
    assert (conv.get("harnessDelay"), conv.get("ctrlDelay")) == ("1", "0")
    assert (
        'name="ctrl.delay"' in ssv
        and '<ssv:Integer value="0"' in ssv.split('name="ctrl.delay"')[1][:80]
    )
    osp = files["osp"].read_text()
    assert "reproduces the harness run with delay = 1" in osp
    assert 'variable="ctrl.delay"' in osp


def test_container_fmu_with_delay_one(delay1_files) -> None:
    """fmpy's container FMU hands u over within the step: with ctrl.delay 1 it is the harness
    with delay 1 (to 1e-9 m; bitwise in practice)."""
    from feeddrive.systems import run_container

    s, files, h = delay1_files
    r = run_container(files["container"], s.n, s.Ts)
    assert float(np.max(np.abs(r["x"] - h["x"]))) <= 1e-9


@pytest.mark.slow
def test_libcosim_at_ts_is_the_harness_with_delay_one(delay1_files) -> None:
    """libcosim on the OSP structure at h = Ts, ctrl.delay 0: the harness with delay 1."""
    pytest.importorskip("libcosimpy", reason="libcosimpy: python/pyproject.toml [test]")
    from feeddrive.systems import run_libcosim_osp

    s, files, h = delay1_files
    r = run_libcosim_osp(files["osp"].parent, s.n, s.Ts, substeps=1)
    assert float(np.nanmax(np.abs(r["x"][1:] - h["x"][1:]))) <= 1e-9


@pytest.mark.slow
def test_libcosim_ssp_without_workers_is_the_harness_with_delay_one(delay1_files) -> None:
    """libcosim on the SSP package (its fixed step on the calling thread, the plant's start
    state x, v as the execution's initial values): the harness with delay 1, and the OSP
    run to the bit."""
    pytest.importorskip("libcosimpy", reason="libcosimpy: python/pyproject.toml [test]")
    from feeddrive.systems import run_libcosim_osp, run_libcosim_ssp

    s, files, h = delay1_files
    r = run_libcosim_ssp(files["ssp"], s.n, s.Ts, substeps=1)
    assert float(np.nanmax(np.abs(r["x"][1:] - h["x"][1:]))) <= 1e-9
    osp = run_libcosim_osp(files["osp"].parent, 400, s.Ts, substeps=1)
    assert np.array_equal(r["x"][1:401], osp["x"][1:])


@pytest.mark.slow
def test_ecos_at_ts_is_the_harness_with_delay_one(delay1_files) -> None:
    """Ecos at h = Ts, ctrl.delay 0: the harness with delay 1."""
    from feeddrive.systems.ecos import load_ecospy, run_ecos

    try:
        load_ecospy()
    except ImportError as e:
        pytest.skip(str(e))
    s, _, h = delay1_files
    r = run_ecos(s)
    assert float(np.max(np.abs(r["x"] - h["x"]))) <= 1e-9


@pytest.mark.parametrize("delay", [0, 1])
def test_c_gauss_seidel_master_is_the_harness_bit_for_bit(fmu_path, delay: int) -> None:
    """tests/c/two_fmus (the C master of `make bench`): plant first, controller second, the
    6 s Sec. 3 loop equal to the harness's with the same delay, to the bit."""
    from pathlib import Path

    from feeddrive.bench_c import run_two_fmus
    from feeddrive.harness.controller_fmu import ControllerFMU

    repo = Path(__file__).resolve().parents[1]
    host = repo / "build" / "tests_c" / "two_fmus"
    make_c(host.name)
    spec = {**state_space_spec(), "delay": delay}
    ref, h = _harness(spec, P)
    values = controller_fmu_parameters(spec, reference=sinusoid_source(A, P, C, P), quantum=1e-7)
    with ControllerFMU(values) as c:
        typed = {k: (c.vr(k), c.vars[k].type[0], float(v)) for k, v in values.items()}
    _, x = run_two_fmus(
        host,
        repo / "build" / "binaries" / "linux64" / "LinearMotorFeedDrive.so",
        repo / "build" / "controller" / "binaries" / "linux64" / "DriveController.so",
        typed,
        ref.n,
        float(ref.x[0]),
        repetitions=1,
    )
    assert np.array_equal(np.asarray(x), h["x"])
