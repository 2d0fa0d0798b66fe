"""`feeddrive plan`: the identification campaign as references and sidecars for a real drive.

The end-to-end tests play a plan through the FMU at a non-paper truth (tests/plan_play.py:
the plan's controller from its sidecars, 100 nm scale, 5 mA current noise on the stage),
write the recordings as a drive would (CSV + the plan's sidecar) and identify them as they
are: every quantity of the truth table within the identification tolerances.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from feeddrive import cli
from feeddrive.experiments.plan import (
    MAP_SPAN,
    PlanError,
    default_limits,
    force_per_volt,
    make_plan,
)
from feeddrive.experiments.plan.files import reference_csv, time_decimals
from feeddrive.harness.controllers import pid_lti_spec
from feeddrive.harness.sidecar import read_sidecar
from feeddrive.identify.pipeline import identify_folder
from feeddrive.model_file import ModelFile, paper_model, save_model
from plan_play import play_plan, read_reference

MAX_PLAN_BYTES = 60e6


def truth_model() -> ModelFile:
    """The paper's drive with mass, friction, current loop, maps and pre-rolling moved."""
    p = dict(paper_model().parameters)
    p["m"] *= 0.93
    p["current.b[2]"] *= 1.05
    p["current.b[3]"] *= 1.05
    p["friction.F_s"] *= 1.12
    p["friction.F_c"] *= 0.92
    p["friction.V_s"] *= 1.25
    p["friction.delta"] = 0.75
    p["friction.sigma2"] *= 1.15
    p["friction.C"] = 7.0e3
    for j in range(1, 6):
        p[f"friction.k[{j}]"] *= 0.9
    for j in (1, 2, 3):
        p[f"cogging.a[{j}]"] *= 1.1
        p[f"ripple.a[{j}]"] *= 0.85
    p["ripple.c[0]"] = 67.0
    return ModelFile(
        name="plan truth",
        effects=paper_model().effects,
        parameters=p,
        description="paper model, perturbed",
    )


def _controllers() -> list:
    """The drive's controller written into the plan's sidecars (the plan's --controller), in
    the registry's general discrete LTI form: a PID with lead (40/120 Hz) as transfer functions
    in z, with back-calculation anti-windup (the tight-limits plan plays the default
    ``pid_lead`` type)."""
    fpv = force_per_volt(paper_model().fmu_parameters())
    return [
        pytest.param(
            pid_lti_spec(
                Kp=3e5,
                Kv=3.5e3,
                Ki=6e6,
                force_per_volt=fpv,
                lead=(40.0, 120.0),
                u_limit=10.0,
                anti_windup={"pole": 0.5},
            ),
            id="lti",
        )
    ]


def _plan(tmp: Path, *options: str, controller: dict | str | None = "default") -> Path:
    out = tmp / "plan"
    args = ["plan", "--out", str(out), *options]
    if controller != "default":
        spec = tmp / "controller.json"
        spec.write_text(json.dumps(controller))
        args += ["--controller", str(spec)]
    assert cli.main(args) == 0
    return out


def _folder_bytes(folder: Path) -> int:
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())


# ---------------------------------------------------------------- the plan's contents
def test_default_plan_files_sidecars_and_size(tmp_path, capsys):
    out = _plan(tmp_path, "--html")
    printed = capsys.readouterr().out
    plan = make_plan(paper_model(), default_limits(paper_model()))
    refs = sorted((out / "reference").glob("*.csv"))
    assert [p.stem for p in refs] == [r.name for r in plan.runs]
    assert sorted(p.stem for p in (out / "sidecar").glob("*.json")) == [r.name for r in plan.runs]
    size = _folder_bytes(out)
    print(f"{len(refs)} runs, {plan.duration:.0f} s of reference, {size / 1e6:.1f} MB")
    assert size < MAX_PLAN_BYTES
    assert f"{len(refs)} runs" in printed
    kinds = {r.kind for r in plan.runs}
    assert kinds == {"prbs", "constant_speed", "force_open_loop", "variable_speed", "prerolling"}
    assert not plan.not_identified
    page = (out / "plan.md").read_text()
    groups: set[str] = set()
    for r in plan.runs:
        assert f"`{r.name}`" in page
        side = read_sidecar(json.loads((out / "sidecar" / f"{r.name}.json").read_text()))
        assert side.extra["kind"] == r.kind and side.Ts == 5e-4
        assert (side.controller is None) == (r.kind == "force_open_loop")
        if r.group in groups:  # the values of one run per group read back
            continue
        groups.add(r.group)
        cols = read_reference(out / "reference" / f"{r.name}.csv")
        assert list(cols) == (
            ["time", "u"]
            if r.kind == "force_open_loop"
            else ["time", "x_ref", "u_add"]
            if r.kind == "prbs"
            else ["time", "x_ref"]
        )
        assert np.all(np.diff(cols["time"]) == pytest.approx(5e-4, abs=1e-12))
        for c, v in r.columns.items():
            assert np.max(np.abs(cols[c] - v)) <= (5e-11 if c == "x_ref" else 5e-8), (r.name, c)
    loads = {r.load for r in plan.runs if r.group == "maps"}
    assert loads == {0.0, 54.9, 272.7}
    assert "<table>" in (out / "plan.html").read_text()


def test_reference_digits_follow_the_sample_time():
    assert time_decimals(5e-4) == 4 and time_decimals(1e-3) == 3 and time_decimals(62.5e-6) == 7
    text = reference_csv({"time": np.arange(3) * 5e-4, "x_ref": np.array([0.1, -1e-10, 0.0])}, 5e-4)
    assert text == "time,x_ref\n0,0.1\n0.0005,-0.0000000001\n0.001,0\n"


def test_limits_scale_the_runs(tmp_path):
    """A short stroke and a low speed: every run inside the stroke less its margins, no speed
    or acceleration above the limits, the open-loop force within --u-limit."""
    m = paper_model()
    lim = default_limits(
        m, stroke=(0.05, 0.15), v_max=0.1, a_max=4.0, u_limit=6.0, loads=(40.0, 200.0)
    )
    plan = make_plan(m, lim)
    for r in plan.runs:
        if r.closed_loop:
            x = r.columns["x_ref"]
            assert 0.055 - 1e-12 <= x.min() and x.max() <= 0.145 + 1e-12, r.name
            v = np.diff(x) / plan.Ts
            assert np.max(np.abs(v)) <= 0.1 * (1 + 1e-9), r.name
            assert np.max(np.abs(np.diff(v))) / plan.Ts <= 4.0 * (1 + 1e-6), r.name
        else:
            assert np.max(np.abs(r.columns["u"])) <= 6.0
    assert {r.load for r in plan.runs} == {0.0, 40.0, 200.0}
    assert max(r.sidecar.get("speed", 0) for r in plan.runs) <= 0.1
    force = next(r for r in plan.runs if r.kind == "force_open_loop")
    m_, F_c = m.parameters["m"], m.parameters["friction.F_c"]
    a_net = (force.sidecar["amplitude"] * force_per_volt(m.fmu_parameters()) - F_c) / m_
    assert a_net * force.sidecar["period"] / 4 <= 0.1 * (1 + 1e-6)  # peak speed
    assert a_net * force.sidecar["period"] ** 2 / 16 >= 4e-3 * (1 - 1e-6)  # travel per swing


def test_what_cannot_be_identified_is_said_at_plan_time(tmp_path, capsys):
    """60 mm of stroke: the maps need two magnet pitches at constant speed; the rest fits."""
    _plan(tmp_path, "--stroke", "0", "0.06")
    printed = capsys.readouterr().out
    plan = make_plan(paper_model(), default_limits(paper_model(), stroke=(0, 0.06)))
    assert list(plan.not_identified) == ["ripple.*, cogging.* (K_f(x), F_cg(x))"]
    assert (
        f"need {MAP_SPAN * 1e3:g} mm"
        in plan.not_identified["ripple.*, cogging.* (K_f(x), F_cg(x))"]
    )
    assert printed.count("not identifiable with these limits") == 1
    page = (tmp_path / "plan" / "plan.md").read_text()
    assert "## Not identifiable with these limits" in page and "magnet pitch" in page
    assert not any(r.group == "maps" for r in plan.runs)
    assert {r.group for r in plan.runs} == {
        "prbs",
        "stribeck",
        "force_open_loop",
        "variable_speed",
        "prerolling",
    }
    assert len({r.sidecar["speed"] for r in plan.runs if r.group == "stribeck"}) >= 6


def test_prerolling_amplitudes_follow_the_nominal_model():
    """The small sinusoid must travel past 2 Delta_N-1 and stay below 2 Delta_N: the paper's
    80 um for the paper's model, the midpoint for a model whose elements are twice as long."""

    def amplitudes(model: ModelFile) -> list[float]:
        plan = make_plan(model, default_limits(model))
        return sorted(r.sidecar["amplitude"] for r in plan.runs if r.kind == "prerolling")

    paper = paper_model()
    assert amplitudes(paper) == [80e-6, 0.5e-3]
    p = dict(paper.parameters)
    for j in range(1, 6):
        p[f"friction.k[{j}]"] *= 0.5
    soft = ModelFile(name="soft", effects=paper.effects, parameters=p)
    delta = [p[f"friction.nu[{j}]"] * p["friction.F_s"] / p[f"friction.k[{j}]"] for j in (4, 5)]
    small, large = amplitudes(soft)
    assert delta[0] + 10e-6 < small < delta[1] - 10e-6 and large > delta[1]


@pytest.mark.parametrize(
    "options, option",
    [
        (["--stroke", "0.1", "0.12"], "--stroke"),
        (["--stroke", "0.2", "0.1"], "--stroke"),
        (["--v-max", "0.0005"], "--v-max"),
        (["--v-max", "0.03"], "--v-max"),
        (["--a-max", "1"], "--a-max"),
        (["--loads", "54.9,1000"], "--loads"),
        (["--loads", "54.9,55"], "--loads"),
        (["--u-limit", "0.6", "--loads", "5"], "--u-limit"),
        (["--loads", "a,b"], "--loads"),
        (["--v-max", "-1"], "--v-max"),
    ],
)
def test_limits_the_campaign_cannot_fit_are_refused(tmp_path, capsys, options, option):
    try:
        status = cli.main(["plan", "--out", str(tmp_path / "p"), *options])
    except SystemExit as e:  # refused by the argument parser
        status = e.code
    assert status == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and option in err and "Traceback" not in err, err
    assert not (tmp_path / "p").exists()


def test_a_bad_controller_file_is_refused_in_one_line(tmp_path, capsys):
    spec = tmp_path / "c.json"
    spec.write_text(json.dumps({"type": "pid", "Kp": 1.0}))
    assert cli.main(["plan", "--out", str(tmp_path / "p"), "--controller", str(spec)]) == 2
    err = capsys.readouterr().err.strip()
    assert "--controller" in err and "Kv" in err and "\n" not in err
    with pytest.raises(PlanError, match="--controller"):
        make_plan(paper_model(), default_limits(paper_model()), {"Kp": 1.0})


@pytest.mark.parametrize("spec", [None, {"type": "cascade_p_pi", "Kv": 120.0, "law": "P-PI"}])
def test_a_controller_the_toolkit_does_not_simulate_is_kept_with_a_note(tmp_path, capsys, spec):
    """A sidecar is information: the drive's own controller description (or null) goes into
    the closed-loop sidecars as given; the plan says a closed-loop replay will be skipped."""
    out = _plan(tmp_path, "--stroke", "0", "0.06", controller=spec)
    assert "replay (validate)" in capsys.readouterr().out
    for side in (out / "sidecar").glob("*.json"):
        meta = json.loads(side.read_text())
        assert meta["controller"] == (None if meta["kind"] == "force_open_loop" else spec)
        assert ("hold_before_record" in meta) == (meta["kind"] != "force_open_loop")


def test_plan_does_not_replace_a_folder_it_did_not_write(tmp_path, capsys):
    out = tmp_path / "p"
    out.mkdir()
    (out / "mine.txt").write_text("keep")
    assert cli.main(["plan", "--out", str(out), "--stroke", "0", "0.05"]) == 2
    assert (out / "mine.txt").read_text() == "keep"


# ---------------------------------------------------------------- plan -> drive -> identify
def _identify_played(tmp_path: Path, plan_dir: Path) -> object:
    truth = truth_model()
    rec = play_plan(plan_dir, truth.fmu_parameters(), tmp_path / "recordings", seed=5)[0].parent
    save_model(truth, tmp_path / "truth.json")
    res = identify_folder(rec, tmp_path / "identified.json", truth=tmp_path / "truth.json")
    print(res.text())
    return res


@pytest.mark.slow
@pytest.mark.parametrize("controller", _controllers())
def test_plan_played_on_the_drive_identifies_the_truth(tmp_path, fmu_path, controller):
    plan_dir = _plan(tmp_path, "--model", str(_paper_file(tmp_path)), controller=controller)
    assert (
        json.loads((plan_dir / "sidecar" / "02_cv_p10mm_s_P0.json").read_text())["controller"]
        == controller
    )
    res = _identify_played(tmp_path, plan_dir)
    failed = [r.quantity for r in res.table if r.ok is False]
    assert not failed, res.text()
    assert not res.skipped
    assert res.model.parameters["m"] == pytest.approx(truth_model().parameters["m"], rel=1e-2)


@pytest.mark.slow
def test_plan_with_tight_limits_identifies_the_truth(tmp_path, fmu_path):
    """100 mm of stroke, 0.1 m/s, 3 m/s^2, +-6 V, loads 40 and 150 N: the maps over 90 mm,
    the Stribeck curve from 0.3 to 60 mm/s, the mass from a smaller force."""
    plan_dir = _plan(
        tmp_path,
        "--stroke",
        "0.05",
        "0.15",
        "--v-max",
        "0.1",
        "--a-max",
        "3.5",
        "--u-limit",
        "6",
        "--loads",
        "40,150",
    )
    plan = make_plan(
        paper_model(),
        default_limits(
            paper_model(),
            stroke=(0.05, 0.15),
            v_max=0.1,
            a_max=3.5,
            u_limit=6.0,
            loads=(40.0, 150.0),
        ),
    )
    assert not plan.not_identified
    assert max(r.sidecar.get("speed", 0) for r in plan.runs) == pytest.approx(0.06)
    res = _identify_played(tmp_path, plan_dir)
    failed = [r.quantity for r in res.table if r.ok is False]
    assert not failed, res.text()
    assert not res.skipped


def _paper_file(tmp: Path) -> Path:
    path = tmp / "nominal.json"
    save_model(paper_model(), path)
    return path
