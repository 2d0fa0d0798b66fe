"""The closed-loop harness: controller specs both ways, the sidecar schema, the FMI fast
path, and every controller type through `feeddrive validate` and `feeddrive diagnose`."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from feeddrive.cli import main as cli
from feeddrive.control.feedforward import FeedforwardOptions
from feeddrive.data import load_run, write_run
from feeddrive.diagnose.workflow import closed_loop_gap
from feeddrive.fmu import FMUError, Plant
from feeddrive.harness import (
    CONTROLLERS,
    SCHEMA,
    Reference,
    Sensors,
    back_and_forth,
    build_sidecar,
    cascade_lti_spec,
    closed_loop_run,
    controller_spec,
    from_positions,
    make_controller,
    pid_lead_spec,
    pid_spec,
    point_to_point,
    prbs,
    read_sidecar,
    reversals,
    simulate_closed_loop,
    sinusoid,
    state_space_spec,
)
from feeddrive.model_file import paper_model, save_model
from feeddrive.validation.replay import validate

PAPER = paper_model()
SPECS = {
    "state_space": state_space_spec(),
    "pid": pid_spec(),
    "pid_lead": pid_lead_spec(),
    "state_space_gms_ff": state_space_spec(feedforward=FeedforwardOptions(friction="gms")),
    "lti": cascade_lti_spec(40.0, 30.0, 0.04, 600.0, anti_windup={"pole": 0.5}),
}


def test_every_registered_type_has_a_spec_here():
    assert {s["type"] for s in SPECS.values()} == set(CONTROLLERS)


@pytest.mark.parametrize("name", SPECS)
def test_spec_to_controller_and_back_through_json(name):
    spec = json.loads(json.dumps(SPECS[name]))
    ref = sinusoid(0.01, 2.0, 0.15, 0.5)
    c = make_controller(spec, ref)
    assert controller_spec(c) == spec
    c2 = make_controller(controller_spec(c), ref)
    c.reset(), c2.reset()
    x = ref.x + 1e-6 * np.sin(np.arange(len(ref.x)))
    u1 = [c.step(float(xk), k) for k, xk in enumerate(x)]
    u2 = [c2.step(float(xk), k) for k, xk in enumerate(x)]
    assert u1 == u2 and np.all(np.isfinite(u1))


def test_pid_to_spec_from_attributes():
    c = make_controller(pid_lead_spec(30.0, 90.0, Kp=1e5), sinusoid(0.01, 2.0, 0.15, 0.1))
    del c.spec  # the PID's own attributes say it too
    assert controller_spec(c) == pid_lead_spec(30.0, 90.0, Kp=1e5)


@pytest.mark.parametrize(
    "spec, match",
    [
        ({"type": "lqr"}, "type 'lqr' is not known"),
        ({"type": "pid", "Kv": 1, "Ki": 1, "force_per_volt": 1}, "'Kp' missing"),
        (dict(pid_spec(), Kp="big"), "Kp = 'big'"),
        (dict(pid_spec(), gain=1.0), r"unknown key\(s\) \['gain'\]"),
        (dict(pid_lead_spec(), lead_zero_hz=200.0), "lead needs 0 < zero_hz < pole_hz"),
        (dict(state_space_spec(), feedforward="gms"), "feedforward must be null or an object"),
        (dict(state_space_spec(), quantum=1e-7), r"unknown key\(s\) \['quantum'\]"),
    ],
)
def test_bad_specs_name_the_key(spec, match):
    with pytest.raises(ValueError, match=match):
        make_controller(spec, sinusoid(0.01, 2.0, 0.15, 0.1))


def test_references():
    r = sinusoid(0.01, 2.0, 0.15, 4.0)
    assert r.n == 8000 and r.x[0] == pytest.approx(0.14) and r.v[0] == 0
    np.testing.assert_allclose(r.time[reversals(r.x)], [1.0, 2.0, 3.0], atol=1e-3)
    p = point_to_point(0.10, 0.12, 0.01, 1.0, dwell=0.2)
    assert p.x[0] == 0.10 and p.x[-1] == pytest.approx(0.12, abs=1e-9)
    assert p.v.max() == pytest.approx(0.01) and p.time[-1] >= 0.2 + 2.0 + 0.2
    b = back_and_forth([0.01, 0.02], stroke=0.01, x0=0.13)
    assert len(reversals(b.x)) == 3 and b.x.max() == pytest.approx(0.14)
    f = from_positions(r.x, r.Ts)
    np.testing.assert_allclose(f.v[1:-1], r.v[1:-1], atol=1e-6)
    u = prbs(5, amplitude=0.3, periods=2)
    assert len(u) == 62 and set(u) == {-0.3, 0.3} and abs(u[:31].sum()) == pytest.approx(0.3)
    with pytest.raises(ValueError, match="Ts"):
        Reference(0.0, r.x, r.v, r.a)


def test_sensors():
    s = Sensors(quantum=1e-7, current_noise=0.01, seed=4)
    np.testing.assert_array_equal(s.quantise(np.array([1.04e-7, 2.6e-7])), [1e-7, 3e-7])
    n = s.current_noise_series(20000)
    assert n.std() == pytest.approx(0.01, rel=0.03)
    np.testing.assert_array_equal(n, s.current_noise_series(20000))
    np.testing.assert_allclose(s.force_disturbance(5), -69.88 * n[:5])
    off = Sensors(current_noise=0.01, noise_on_stage=False)
    assert not off.force_disturbance(5).any()
    assert Sensors.from_json(s.to_json()) == s
    with pytest.raises(ValueError, match="sensors: unknown key"):
        Sensors.from_json({"quanta": 1e-7})
    with pytest.raises(ValueError, match="quantum"):
        Sensors(quantum=-1.0)


def test_sidecar_build_and_read():
    s = Sensors(seed=7)
    meta = build_sidecar("closed_loop", 5e-4, pid_spec(), s, F_load=54.9, name="r1")
    assert meta["schema"] == SCHEMA and meta["sensors"]["seed"] == 7
    side = read_sidecar(json.loads(json.dumps(meta)))
    assert (side.experiment, side.Ts, side.controller, side.sensors, side.F_load) == (
        "closed_loop",
        5e-4,
        pid_spec(),
        s,
        54.9,
    )
    assert side.extra == {"name": "r1"}
    assert read_sidecar({}).controller is None and read_sidecar(None).sensors == Sensors()
    assert side.ignored == [] and side.note_line() is None
    # what is not understood is named and left out, never refused
    for bad, named in [
        ({"Ts": 0}, "Ts"),
        ({"controller": 3}, "controller"),
        ({"schema": "x/2"}, "'x/2'"),
        ({"sensors": {"seed": "a"}}, "sensors.seed"),
        ({"controller": {"Kp": 1}}, "controller"),
        ({"controller": dict(pid_spec(), law="PID")}, "controller.law"),
    ]:
        side = read_sidecar(bad, where="r.json")
        assert side.note_line("r.json").startswith("r.json: ") and named in side.note_line()
    assert read_sidecar({"sensors": {"seed": "a", "quantum": 5e-8}}).sensors == Sensors(
        quantum=5e-8
    )
    with pytest.raises(ValueError, match="schema fields"):
        build_sidecar("x", 5e-4, None, s, schema="x/2")


def test_fast_path_uses_its_own_handles_and_reports_fmu_errors(fmu_path):
    with Plant() as p:
        with pytest.raises(FMUError, match="not started"):
            p.raw_calls()
        p.start({"x": 0.15})
        io = p.raw(["x", "v"])
        np.testing.assert_allclose(io.get(), [0.15, 0.0])
        assert io.calls.do_step is not p.fmu.dll["fmi2DoStep"]
        with pytest.raises(FMUError, match="fmi2SetReal"):
            p.raw(["x"]).set([0.2])  # a state is not settable after init
    ref = sinusoid(0.03, 6.0, 0.15, 1.0)
    with Plant() as p:
        res = simulate_closed_loop(p, make_controller(state_space_spec(), ref), ref.n, ref.x[0])
    assert len(res["x"]) == ref.n + 1 and np.max(np.abs(res["x"] - ref.x)) < 50e-6


def _write(tmp_path, name, spec, F_load=0.0):
    ref = sinusoid(0.01, 2.0, 0.15, 2.0)
    run, _ = closed_loop_run(
        PAPER.fmu_parameters(),
        spec,
        ref,
        Sensors(seed=11),
        experiment="harness_test",
        F_load=F_load,
        name=name,
    )
    path = tmp_path / f"{name}.csv"
    write_run(run, path)
    return path


@pytest.mark.parametrize("name", SPECS)
def test_every_controller_type_through_validate_and_diagnose(name, tmp_path, capsys):
    path = _write(tmp_path, name, SPECS[name], F_load=20.0)
    run = load_run(path)
    # validate: the replay of the true model is within the sensors' effect of the run
    assert cli(["validate", str(path)]) == 0
    out = capsys.readouterr().out
    m = re.search(
        r"reversal peak .*: ([\d.]+) µm\n.*elsewhere max: ([\d.]+) µm\n.*rms: ([\d.]+) µm", out
    )
    assert m, out
    peak, band, rms = map(float, m.groups())
    assert peak < 2.0 and band < 2.0 and 0.0 < rms < 1.0, out
    rep = validate(run, PAPER)
    assert np.all(np.isfinite(list(rep.force.values()))) and rep.force["rms"] < 0.5
    # diagnose: its closed-loop re-simulation accepts the run and finds the same small gap
    gap = closed_loop_gap([run], PAPER)
    assert gap is not None and gap["position_error_max_m"] < 2e-6
    # diagnose quantises x_sim, validate does not: they differ by up to the rounding, rms
    # quantum/sqrt(12) = 29 nm
    assert gap["position_error_rms_m"] == pytest.approx(rms * 1e-6, rel=0.05, abs=3e-8)
    save_model(PAPER, tmp_path / "paper.json")
    assert (
        cli(
            [
                "diagnose",
                str(path),
                "--model",
                str(tmp_path / "paper.json"),
                "--out",
                str(tmp_path / "d"),
                "--max-steps",
                "1",
            ]
        )
        == 0
    )
    doc = json.loads((tmp_path / "d" / "diagnosis.json").read_text())
    assert not any("closed-loop gap not computed" in n for n in doc["notes"]), doc["notes"]


def test_validate_refuses_a_sidecar_that_contradicts_its_csv(tmp_path, capsys):
    path = _write(tmp_path, "bad", pid_spec())
    meta = json.loads(path.with_suffix(".json").read_text())
    meta["Ts"] = 1e-3
    path.with_suffix(".json").write_text(json.dumps(meta))
    assert cli(["validate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "bad.json" in err and "Ts = 0.001 s" in err and "0.0005 s" in err


def test_raw_io_follows_a_restart_and_refuses_a_closed_plant():
    """A RawIO made before start() again reads the new instance (never the freed one); after
    close() it raises instead of touching freed memory."""
    plant = Plant({"m": 16.1})
    plant.start({"x": 0.1})
    io, inp = plant.raw(["x", "m"]), plant.raw(["u"])
    assert list(io.get()) == [0.1, 16.1]
    plant.start({"x": 0.2})
    assert list(io.get()) == [0.2, 16.1]
    inp.set([0.25])
    assert plant.get(["u"])["u"] == 0.25
    plant.close()
    with pytest.raises(FMUError, match="not started"):
        io.get()
