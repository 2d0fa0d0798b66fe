"""Virtual identification experiments: DATA.md runs that look like measurements.

One quick campaign (a few seconds of simulation) on the paper's model is shared by the tests.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from feeddrive.cli import main as cli_main
from feeddrive.data import KNOWN_COLUMNS, load_run, write_run
from feeddrive.diagnose.workflow import closed_loop_gap
from feeddrive.experiments import campaign as campaign_mod
from feeddrive.experiments.campaign import GROUPS, campaign, write_campaign
from feeddrive.experiments.constant_speed import PAPER_LOADS, constant_speed_runs
from feeddrive.experiments.force_open_loop import force_open_loop_runs
from feeddrive.experiments.prbs import prbs_runs, prbs_sequence
from feeddrive.harness.sensors import Sensors
from feeddrive.model_file import PARAMETER_NAMES, paper_model
from feeddrive.paper import paper_parameters
from feeddrive.physics.position_maps import force_constant
from feeddrive.validation.replay import validate_file

QUANTUM = 1e-7
KINDS = {"prbs", "constant_speed", "force_open_loop", "variable_speed", "prerolling"}


@pytest.fixture(scope="module")
def params() -> dict:
    return paper_model().fmu_parameters()


@pytest.fixture(scope="module")
def runs(params) -> dict:
    return campaign(params, Sensors(seed=1), quick=True)


def all_runs(runs):
    return [r for g in GROUPS for r in runs[g]]


def test_campaign_has_every_experiment(runs):
    names = [r.meta["name"] for r in all_runs(runs)]
    assert len(names) == len(set(names)), "file stems must be unique"
    assert {
        "prbs",
        "force_open_loop",
        "variable_speed",
        "prerolling_A80um",
        "prerolling_A500um",
    } <= set(names)
    assert {f"cv_{d}1mm_s_P{P:g}" for d in "pm" for P in PAPER_LOADS} <= set(names)
    assert len(runs["cogging_ripple"]) == 6
    assert len(runs["stribeck"]) >= 4  # >= 2 speeds, both directions
    for r in all_runs(runs):
        assert r.meta["kind"] in KINDS


def test_runs_round_trip_through_data_md(runs, tmp_path):
    for r in all_runs(runs):
        path = tmp_path / f"{r.meta['name']}.csv"
        write_run(r, path)
        back = load_run(path)
        for c in ("time", "u", "i", "x", "F_load"):
            np.testing.assert_array_equal(getattr(back, c), getattr(r, c), err_msg=f"{path}:{c}")
        assert (back.x_ref is None) == (r.x_ref is None)
        assert back.meta == json.loads(json.dumps(r.meta))
        assert np.allclose(np.diff(back.time), 5e-4, rtol=1e-9, atol=1e-12)


def test_meta_describes_the_experiment_not_the_model(runs):
    for r in all_runs(runs):
        assert r.meta["Ts"] == 5e-4
        assert "controller" in r.meta
        assert not set(r.meta) & (set(PARAMETER_NAMES) - {"Ts"}), r.meta["name"]
    for r in runs["cogging_ripple"] + runs["stribeck"]:
        assert {"speed", "direction", "P"} <= set(r.meta)


def test_position_is_quantised_at_100_nm(runs):
    for r in all_runs(runs):
        q = r.x / QUANTUM
        assert np.max(np.abs(q - np.round(q))) < 1e-6, r.meta["name"]
        steps = np.abs(np.diff(r.x))
        assert np.min(steps[steps > 0]) == pytest.approx(QUANTUM, rel=1e-6)


def test_constant_speed_within_1_percent_over_cruise(runs):
    for r in runs["cogging_ripple"] + runs["stribeck"]:
        target = r.meta["direction"] * r.meta["speed"]
        v_ref = np.diff(r.x_ref) / r.meta["Ts"]
        cruise = np.flatnonzero(np.isclose(v_ref, target, rtol=1e-6))
        assert cruise.size * r.meta["Ts"] > 1.0, r.meta["name"]
        k = cruise[cruise.size // 10 : -cruise.size // 10]  # the settled part of the cruise
        v = np.polyfit(r.time[k], r.x[k], 1)[0]
        assert v == pytest.approx(target, rel=0.01), r.meta["name"]


def test_loads_are_in_f_load_and_act_as_p(runs, params):
    """F_load = P; and K_f(x)(i(P) - i(0)) over the cruise = P (Eq. 3: same friction and
    cogging at the same x and v, so the current difference is the load alone)."""
    by = {(r.meta["P"], r.meta["direction"]): r for r in runs["cogging_ripple"]}
    for (P, _d), r in by.items():
        assert np.all(r.F_load == P)
        assert r.meta["P"] == P
    grid = np.linspace(0.1485, 0.1515, 61)
    for P in PAPER_LOADS[1:]:
        for d in (1, -1):
            diffs = []
            for load in (P, 0.0):
                r = by[(load, d)]
                moving = np.abs(np.gradient(r.x_ref, r.time)) > 0.99e-3
                order = np.argsort(r.x[moving])
                i_x = np.interp(grid, r.x[moving][order], r.i[moving][order])
                diffs.append(i_x)
            dF = np.mean(force_constant(grid, params) * (diffs[0] - diffs[1]))
            assert dF == pytest.approx(P, rel=0.02), (P, d)


def test_prbs_is_in_u_with_its_amplitude(runs):
    r = runs["prbs"][0]
    k0, A = r.meta["prbs_start"], r.meta["amplitude"]
    assert r.meta["order"] == 11 and r.meta["prbs_period"] == 2047
    s = prbs_sequence(11, A, r.meta["periods"])
    assert r.n - k0 >= 2047
    u = r.u[k0 : k0 + s.size]
    # the controller's reaction is low-pass (~20 Hz) and nearly uncorrelated with a white
    # sequence: the projection of u on the PRBS is the PRBS itself
    assert np.dot(u, s) / np.dot(s, s) == pytest.approx(1.0, abs=0.05)
    assert np.std(r.u[:k0]) < 0.1 * A  # before: only the holding controller
    jumps = np.diff(u)[np.diff(s) != 0] / np.diff(s)[np.diff(s) != 0]
    assert np.median(jumps) == pytest.approx(1.0, abs=0.05)
    assert np.ptp(r.i[k0:]) > 0.5 * 2 * A  # the current follows (G(1) = 1.13 A/V)


def test_current_is_sampled_with_eq2_delay(runs):
    """Measured i[k] follows Eq. 2: impulse response h_0 = h_1 = 0, h_2 = b2, h_3 = a1 b2 + b3
    (the DAQ samples the current the FMU computes at t_k, not the value held before t_k).

    FIR least squares is unbiased here: the current noise at k is white and independent of
    u up to k (the controller reads x(t_k), moved by noise before k only)."""
    r = runs["prbs"][0]
    L = 30
    k = np.arange(r.meta["prbs_start"] + L, r.n)
    A = np.column_stack([r.u[k - j] for j in range(L)] + [np.ones(k.size)])
    h = np.linalg.lstsq(A, r.i[k], rcond=None)[0][:L]
    b2, b3, a1 = 0.057909, 0.057909 * 0.7461, 1.404
    assert abs(h[0]) < 0.005 and abs(h[1]) < 0.005
    assert h[2] == pytest.approx(b2, abs=0.005)
    assert h[3] == pytest.approx(a1 * b2 + b3, abs=0.005)
    assert np.sum(h) == pytest.approx(1.126, rel=0.05)  # G(1), Eq. 2's DC gain


def test_variable_speed_never_reverses(runs):
    r = runs["variable_speed"][0]
    t0, t1 = r.meta["variable_phase"]
    assert r.time[-1] == pytest.approx(t1)
    var = r.time >= t0
    # while sliding at >= v_min = 5 mm/s (25 quanta per sample) x strictly increases
    assert np.all(np.diff(r.x[var]) > 0)
    v = np.diff(r.x[var]) / r.meta["Ts"]
    assert np.percentile(v, 1) > 0.5 * r.meta["v_min"]
    assert np.percentile(v, 99) < 1.5 * r.meta["v_max"]
    # during the ramp from rest only sub-micrometre jitter of the stage at rest (noise)
    assert np.all(r.x >= np.maximum.accumulate(r.x) - 1e-6)


def test_prerolling_amplitudes(runs):
    small, large = sorted(runs["prerolling"], key=lambda r: r.meta["amplitude"])
    A, c = small.meta["amplitude"], small.meta["centre"]
    assert A == pytest.approx(80e-6)
    # within the amplitude (+1 um = 10 quanta of closed-loop overshoot at reversals)
    assert np.max(np.abs(small.x - c)) <= A + 1e-6
    assert np.ptp(small.x) > 1.8 * A  # and it does move
    # the large one travels well beyond the pre-rolling range (2 Delta_5 ~ 0.23 mm)
    assert np.ptp(large.x) > 1.9 * large.meta["amplitude"] > 0.46e-3


def test_force_open_loop_moves_inside_the_stroke(runs, params):
    r = runs["force_open_loop"][0]
    assert r.meta["controller"] is None and r.x_ref is None
    assert not r.meta["stopped_at_stroke_limit"]
    assert params["stroke.x_min"] < r.x.min() and r.x.max() < params["stroke.x_max"]
    assert np.ptp(r.x) > 5e-3
    assert set(np.round(np.unique(r.u), 9)) == {-1.0, 0.0, 1.0}


def test_force_open_loop_stops_before_leaving_the_stroke(params):
    r = force_open_loop_runs(params, Sensors(seed=2), bias=1.0, n_periods=3)[0]
    assert r.meta["stopped_at_stroke_limit"]
    assert r.x.max() < params["stroke.x_max"] - 1.9e-3


def test_seeds_reproduce_and_differ(params):
    a = prbs_runs(params, Sensors(seed=5), periods=1)[0]
    b = prbs_runs(params, Sensors(seed=5), periods=1)[0]
    c = prbs_runs(params, Sensors(seed=6), periods=1)[0]
    for col in ("u", "i", "x"):
        np.testing.assert_array_equal(getattr(a, col), getattr(b, col))
    assert not np.array_equal(a.i, c.i)
    assert not np.array_equal(a.x, c.x)
    # the noise is the only difference: it is ~5 mA rms in i
    assert 0.003 < np.std(a.i - c.i) / np.sqrt(2) < 0.008


def test_runs_within_one_experiment_get_different_noise(params):
    runs = constant_speed_runs(
        params, Sensors(seed=3), speeds=(10e-3,), segment=(0.15, 0.155), dwell=0.05
    )
    assert len(runs) == 2 and runs[0].meta["sensors"]["seed"] != runs[1].meta["sensors"]["seed"]


def test_write_campaign_names_files(tmp_path, monkeypatch):
    real_plan = campaign_mod.plan
    monkeypatch.setattr(campaign_mod, "plan", lambda quick: real_plan(quick)[:1])  # PRBS only
    paths = write_campaign(tmp_path, model=paper_parameters(), seed=1, quick=True, fmt="csv")
    assert [p.name for p in paths] == ["prbs.csv"]
    assert (tmp_path / "prbs.json").is_file()
    r = load_run(paths[0])
    assert r.meta["kind"] == "prbs" and set(r.columns()) <= set(KNOWN_COLUMNS)


def test_bad_options_raise(params):
    with pytest.raises(ValueError, match="speed"):
        constant_speed_runs(params, Sensors(), speeds=(-1e-3,))
    with pytest.raises(ValueError, match="segment"):
        constant_speed_runs(params, Sensors(), segment=(0.2, 0.1))
    with pytest.raises(TypeError, match="model"):
        write_campaign(None, model=42)  # type: ignore[arg-type]


def test_every_run_is_accepted_by_validate_and_diagnose(runs, tmp_path):
    """Each run the campaign writes is read back by `feeddrive validate` (replay + force
    residual) and by the diagnosis's closed-loop re-simulation, with finite numbers.

    Bounds: the true model's force residual stays below 10 N (under loads up to 272.7 N;
    ~1 N unloaded), the replayed position within 10 um rms of the run (0.2-0.4 um; the PRBS
    run ~5 um: its excitation on u is not part of the controller and is not replayed)."""
    model = paper_model()
    loaded = []
    for r in all_runs(runs):
        path = tmp_path / f"{r.meta['name']}.csv"
        write_run(r, path)
        rep = validate_file(path)
        assert np.all(np.isfinite(list(rep.force.values()))) and rep.force["rms"] < 10.0, path.name
        if r.meta["controller"] is None:
            assert rep.position is None
        else:
            p = rep.position
            assert p is not None and np.isfinite(p.rms) and p.rms < 10e-6, (path.name, p)
        loaded.append(load_run(path))
    gap = closed_loop_gap(loaded, model)
    assert gap is not None and np.isfinite(gap["position_error_rms_m"])
    assert gap["position_error_rms_m"] < 10e-6


def test_repeats_give_independent_noise_and_suffixed_names(tmp_path, monkeypatch):
    """--repeats K: every run K times, names _r1.._rK, repeat 1 = the campaign without repeats
    (same seed, same samples), repeat 2 with other noise: the measured position differs by
    encoder steps (the sensor's quantum) but the runs follow the same motion (within a few
    quanta plus noise: the current noise moves the loop by well under 1 um)."""
    real_plan = campaign_mod.plan
    monkeypatch.setattr(campaign_mod, "plan", lambda quick: real_plan(quick)[:1])  # PRBS only
    one = write_campaign(tmp_path / "one", model=paper_parameters(), seed=1, quick=True)
    three = write_campaign(
        tmp_path / "three", model=paper_parameters(), seed=1, quick=True, repeats=3
    )
    assert [p.name for p in three] == ["prbs_r1.csv.gz", "prbs_r2.csv.gz", "prbs_r3.csv.gz"]
    r0, r1, r2 = load_run(one[0]), load_run(three[0]), load_run(three[1])
    assert r1.meta["repeat"] == 1 and r2.meta["repeat"] == 2
    assert r1.meta["sensors"]["seed"] == r0.meta["sensors"]["seed"] != r2.meta["sensors"]["seed"]
    np.testing.assert_array_equal(r1.x, r0.x)
    assert np.any(r2.x != r1.x) and np.max(np.abs(r2.x - r1.x)) < 5e-6
    with pytest.raises(ValueError, match="repeats"):
        write_campaign(tmp_path / "bad", model=paper_parameters(), repeats=0)


@pytest.mark.parametrize("value", ("0", "101", "x"))
def test_cli_experiments_rejects_bad_repeats(tmp_path, capsys, value):
    with pytest.raises(SystemExit) as e:
        cli_main(["experiments", "--out", str(tmp_path / "x"), "--repeats", value])
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert "error: argument --repeats" in err and not (tmp_path / "x").exists()


def test_campaign_writes_gzip_runs_that_load_back_as_written(tmp_path, monkeypatch):
    """The default format: ``<name>.csv.gz`` + ``<name>.json``, each loading back to the
    values the campaign made within half a digit of the recording's decimals (positions
    5e-11 m, voltages and currents 5e-8), bit for bit what ``--format csv`` writes."""
    from feeddrive.data import RECORDING_DECIMALS

    real_plan = campaign_mod.plan
    jobs = [j for j in real_plan(True) if j[0] in ("prbs", "cogging_ripple")][:3]
    monkeypatch.setattr(campaign_mod, "plan", lambda quick: jobs)
    made = []
    real_write = campaign_mod.write_run
    monkeypatch.setattr(
        campaign_mod,
        "write_run",
        lambda run, path, dec: (made.append(run), real_write(run, path, dec)),
    )
    assert cli_main(["experiments", "--out", str(tmp_path / "gz")]) == 0
    gz = sorted((tmp_path / "gz").iterdir())
    assert [p.name for p in gz if not p.name.startswith(".")] == sorted(
        f"{r.meta['name']}{ext}" for r in made for ext in (".csv.gz", ".json")
    )
    for run in made:
        back = load_run(tmp_path / "gz" / f"{run.meta['name']}.csv.gz")
        assert back.meta["kind"] == run.meta["kind"] and back.n == run.n
        for name, d in RECORDING_DECIMALS.items():
            if name in run.columns():
                err = np.max(np.abs(back.columns()[name] - run.columns()[name]))
                assert err <= 0.5 * 10.0**-d * 1.001, (run.meta["name"], name, err)
    made.clear()
    assert cli_main(["experiments", "--out", str(tmp_path / "plain"), "--format", "csv"]) == 0
    for run in made:
        a = load_run(tmp_path / "plain" / f"{run.meta['name']}.csv")
        b = load_run(tmp_path / "gz" / f"{run.meta['name']}.csv.gz")
        for name, arr in a.columns().items():
            np.testing.assert_array_equal(b.columns()[name], arr, err_msg=name)


def test_cli_experiments_rejects_an_unknown_format(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        cli_main(["experiments", "--out", str(tmp_path / "x"), "--format", "parquet"])
    assert e.value.code == 2
    assert "error: argument --format" in capsys.readouterr().err and not (tmp_path / "x").exists()
    with pytest.raises(ValueError, match="format"):
        write_campaign(tmp_path / "y", model=paper_parameters(), fmt="csv.bz2")
    assert not (tmp_path / "y").exists()
