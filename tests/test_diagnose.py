"""Discrepancy workflow: residual, localisation, scoring rules, outputs, loop behaviour."""

from __future__ import annotations

import json

import numpy as np
import pytest

from diagnosis_runs import make_runs, simulate_run, sinusoid_reference
from feeddrive.cli import main as feeddrive_cli
from feeddrive.data import write_run
from feeddrive.diagnose.localise import displacement_since_reversal, spatial_spectrum
from feeddrive.harness import controller_spec, make_controller, pid_spec
from feeddrive.model_file import load_model, paper_model, save_model
from feeddrive.report.diagnosis import write_diagnosis
from feeddrive.residual import force_residual
from session_cache import diagnose

PAPER = paper_model()


def _runs(truth, seed, noise=0.005, cs=True):
    return make_runs(truth, seed, noise=noise, cs=cs, cs_seed_offset=1)


def test_displacement_since_reversal():
    t = np.linspace(0, 2, 2001)
    x = 0.1 + 1e-3 * np.sin(2 * np.pi * t)  # turning points at t = 0.25, 0.75, ...
    d = displacement_since_reversal(x)
    k = np.searchsorted(t, 0.5)
    assert d[k] == pytest.approx(1e-3, abs=2e-6)  # from the top at 0.25 to mid at 0.5
    k = np.searchsorted(t, 0.75)
    assert d[k] == pytest.approx(2e-3, abs=2e-5)


def test_spatial_spectrum_finds_a_planted_wavelength():
    from feeddrive.residual import RunResidual

    n = 20000
    x = np.linspace(0.12, 0.18, n)
    r = 0.8 * np.sin(2 * np.pi * x / 0.0125) + 0.05 * np.random.default_rng(0).standard_normal(n)
    q = RunResidual(
        name="t",
        Ts=5e-4,
        K=np.ones(1),
        time=np.arange(n) * 5e-4,
        x=x,
        v=np.full(n, 0.01),
        a=np.zeros(n),
        i=None,
        F_motor=np.zeros(n),
        F_app=np.zeros(n),
        F_f=np.zeros(n),
        stuck=np.zeros(n, bool),
        r=r,
        valid=np.ones(n, bool),
        force_source="",
    )
    lams, amps = spatial_spectrum([q])
    k = int(np.argmax(amps))
    assert lams[k] == pytest.approx(0.0125, rel=0.01)
    assert amps[k] == pytest.approx(0.8, rel=0.05)


def test_residual_of_the_true_model_is_at_the_noise_floor():
    # the model that made the data leaves only the filtered current noise (5 mA * 70 N/A *
    # ||K|| ~ 0.07 N) and the GMS-along-the-measured-path error at reversals
    run = simulate_run(PAPER, sinusoid_reference(6.0), current_noise=0.005, seed=3)
    q = force_residual(run, PAPER)
    assert q.rms < 0.12
    q2 = force_residual(run, PAPER.with_effect("offset_force", True, **{"offset.F": 2.0}))
    assert np.nanmean(q2.r) == pytest.approx(-2.0, abs=0.05)  # sign: r = missing resistive force


def test_complete_model_gets_nothing_named(tmp_path):
    diag = diagnose(_runs(PAPER, seed=31), PAPER, closed_loop=False)
    write_diagnosis(diag, tmp_path)
    assert diag.steps == []
    doc = json.loads((tmp_path / "diagnosis.json").read_text())
    assert doc["steps"] == [] and "no candidate" in doc["stop"]["reason"]
    assert doc["verdict"]["verdict"] == "explained"
    assert doc["verdict"]["x_noise_floor"] < 3.0
    assert load_model(tmp_path / "model.json").parameters == PAPER.parameters


def test_two_hidden_effects_are_found_in_turn(tmp_path):
    truth = PAPER.with_effect(
        "asymmetric_friction", True, **{"asymmetry.dF": 4.0, "asymmetry.dsigma2": 30.0}
    )
    start = PAPER.with_effect("mass", True, m=14.0)
    diag = diagnose(_runs(truth, seed=41, noise=0.003), start, closed_loop=False)
    write_diagnosis(diag, tmp_path)
    assert diag.named[:2] == ["asymmetric_friction", "mass"]
    assert len(diag.steps) == 2
    assert abs(diag.model.parameters["m"] - 16.1) < 0.4
    assert abs(diag.model.parameters["asymmetry.dF"] - 4.0) < 0.3
    g0 = diag.steps[0].gap_before["force_rms_N"]
    assert diag.steps[1].gap_after["force_rms_N"] < 0.1 * g0
    # outputs
    doc = json.loads((tmp_path / "diagnosis.json").read_text())
    assert [s["effect"] for s in doc["steps"]] == ["asymmetric_friction", "mass"]
    assert [s["decision"] for s in doc["steps"]] == ["missing_effect", "refinement"]
    assert doc["steps"][1]["refinement"]["force_change_rms_N"] > 0.0
    assert doc["verdict"]["verdict"] == "explained"
    s0 = doc["steps"][0]
    for key in ("effect", "evidence", "parameters", "gap_before", "gap_after"):
        assert key in s0
    assert s0["parameters"]["asymmetry.dF"]["unit"] == "N"
    assert s0["evidence"]["heldout_improvement"] > 0.5
    html = (tmp_path / "report.html").read_text()
    for png in (
        "residual_time.png",
        "residual_position.png",
        "residual_reversal.png",
        "step1_asymmetric_friction.png",
        "step2_mass.png",
    ):
        assert png in html and (tmp_path / png).stat().st_size > 1000
    m = load_model(tmp_path / "model.json")
    assert m.effects["asymmetric_friction"] and m.parameters["m"] == diag.model.parameters["m"]


def test_sec3_sinusoid_static_friction_names_prerolling_and_reversal_error_shrinks(tmp_path):
    # the Sec. 3 sinusoid (30 mm, 6 s, mid-stroke), one run, a
    # static-friction model: prerolling is named and the closed-loop reversal error of the
    # re-simulated model shrinks
    run = simulate_run(PAPER, sinusoid_reference(12.0), current_noise=0.005, seed=51, name="sec3")
    path = tmp_path / "sec3.csv"
    write_run(run, path)
    model_path = tmp_path / "static.json"
    save_model(PAPER.with_effect("prerolling", False), model_path)
    out = tmp_path / "out"
    assert (
        feeddrive_cli(
            [
                "diagnose",
                str(path),
                "--model",
                str(model_path),
                "--out",
                str(out),
                "--max-steps",
                "1",
            ]
        )
        == 0
    )
    doc = json.loads((out / "diagnosis.json").read_text())
    s = doc["steps"][0]
    assert s["effect"] == "prerolling"
    assert s["evidence"]["where"][0]["regime"].startswith("since_reversal")
    rb, ra = s["gap_before"]["reversal_error_max_m"], s["gap_after"]["reversal_error_max_m"]
    assert ra < 0.5 * rb, (rb, ra)
    assert s["gap_after"]["force_rms_N"] < 0.1 * s["gap_before"]["force_rms_N"]


def test_pid_sidecar_round_trip():
    ref = sinusoid_reference(0.1)
    c = make_controller(pid_spec(), ref)
    c2 = make_controller(controller_spec(c), ref)
    assert (c2.Kp, c2.Kv, c2.Ki) == (c.Kp, c.Kv, c.Ki)
    with pytest.raises(ValueError, match="Kp"):
        make_controller({"type": "pid", "Kv": 1, "Ki": 1, "force_per_volt": 1}, ref)


def test_diagnose_rejects_no_runs():
    with pytest.raises(ValueError, match="no runs"):
        diagnose([], PAPER)


def test_too_short_run_is_rejected_with_its_name():
    run = simulate_run(PAPER, sinusoid_reference(0.1), seed=1, name="tiny")
    with pytest.raises(ValueError, match=r"tiny.*usable samples"):
        diagnose([run], PAPER, closed_loop=False)


def test_diagnose_command_writes_its_files_and_refuses_bad_input(tmp_path, capsys):
    run = simulate_run(
        PAPER, sinusoid_reference(3.0, period=3.0), current_noise=0.005, seed=61, name="short"
    )
    write_run(run, tmp_path / "short.csv")
    save_model(PAPER, tmp_path / "paper.json")
    assert (
        feeddrive_cli(
            [
                "diagnose",
                str(tmp_path / "short.csv"),
                "--model",
                str(tmp_path / "paper.json"),
                "--out",
                str(tmp_path / "o"),
                "--max-steps",
                "1",
            ]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert "stopped: no candidate" in out and "verdict: explained" in out
    assert json.loads((tmp_path / "o" / "diagnosis.json").read_text())["steps"] == []
    assert (tmp_path / "o" / "report.html").stat().st_size > 500
    assert (
        feeddrive_cli(
            [
                "diagnose",
                str(tmp_path / "missing.csv"),
                "--model",
                str(tmp_path / "paper.json"),
                "--out",
                str(tmp_path / "o2"),
            ]
        )
        == 2
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "missing.csv" in err[0] and "Traceback" not in err[0]
    assert not (tmp_path / "o2").exists()
