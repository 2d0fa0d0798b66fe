"""The ISO 230-4 circular test: the evaluation on synthetic paths with known G, H, G(b) and
glitches; the circle reference; the X-Y master of 4 FMUs against the harness; the glitches
against Sec. 4 with and without GMS feedforward; the symmetric table; the CLI; the study kind."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from feeddrive.cli import main
from feeddrive.experiments import sec4
from feeddrive.fmu import Plant
from feeddrive.harness import make_controller, simulate_closed_loop
from feeddrive.harness.controllers import state_space_spec
from feeddrive.study import RunTask, StudyError, cases, parse_study, run_case
from feeddrive.xy.circle_test import circular_case, controller_values, run_circle
from feeddrive.xy.circular import bidirectional_deviation, fit_circle, glitches, hysteresis, trace
from feeddrive.xy.machine import identical_axes, shift_magnets, xy_axes
from feeddrive.xy.path import circle_path
from feeddrive.xy.system import circle_system, master_run, run_libcosim_xy, write_xy_osp
from feeddrive.xy.table import AxisLoop, simulate_axes

R = 0.01
TH = np.linspace(0, 2 * np.pi, 7200, endpoint=False)


# ------------------------------------------------------------------ evaluation, synthetic
def test_ellipse_has_G_equal_to_the_difference_of_its_semi_axes() -> None:
    a, b = R + 3e-6, R - 2e-6  # radii from the centre run from b to a
    t = trace(0.15 + a * np.cos(TH), 0.12 + b * np.sin(TH), R)
    assert abs(t.fit.cx - 0.15) < 1e-12 and abs(t.fit.cy - 0.12) < 1e-12
    assert t.G == pytest.approx(a - b, rel=1e-6)
    assert t.F_max == pytest.approx(3e-6, rel=1e-5) and t.F_min == pytest.approx(-2e-6, rel=1e-5)


def test_shifted_circle_has_no_circular_deviation_and_its_radius_error_as_F() -> None:
    t = trace(0.1507 + (R + 4e-6) * np.cos(TH), 0.1493 + (R + 4e-6) * np.sin(TH), R)
    assert (t.fit.cx, t.fit.cy) == (
        pytest.approx(0.1507, abs=1e-12),
        pytest.approx(0.1493, abs=1e-12),
    )
    assert t.G < 1e-12
    assert t.F_max == pytest.approx(4e-6, abs=1e-12) and t.F_min == pytest.approx(4e-6, abs=1e-12)


def test_hysteresis_of_two_offset_circles_is_twice_the_offset() -> None:
    # CW centred at +d, CCW at -d: about the common centre r_cw - r_ccw = 2 d cos(theta)
    d = 1.5e-6
    cw = trace(0.15 + d + R * np.cos(-TH), 0.15 + R * np.sin(-TH), R, "cw")
    ccw = trace(0.15 - d + R * np.cos(TH + 0.3e-3), 0.15 + R * np.sin(TH + 0.3e-3), R, "ccw")
    assert cw.G < 1e-12 and ccw.G < 1e-12  # each path is a perfect circle
    assert hysteresis(cw, ccw) == pytest.approx(2 * d, rel=1e-4)
    assert bidirectional_deviation(cw, ccw) == pytest.approx(2 * d, rel=1e-4)


def test_hysteresis_of_a_radius_offset() -> None:
    h = 2e-6
    cw = trace(0.15 + (R + h / 2) * np.cos(TH), 0.15 + (R + h / 2) * np.sin(TH), R, "cw")
    ccw = trace(0.15 + (R - h / 2) * np.cos(TH), 0.15 + (R - h / 2) * np.sin(TH), R, "ccw")
    assert hysteresis(cw, ccw) == pytest.approx(h, rel=1e-9)
    assert cw.F_max == pytest.approx(h / 2, abs=1e-12)


@pytest.mark.parametrize("direction", ["ccw", "cw"])
def test_glitches_of_known_spikes_after_each_reversal(direction: str) -> None:
    """A 10 um (X) and 6 um (Y) spike 8 deg after each transition, a 1 um undulation."""
    s = 1.0 if direction == "ccw" else -1.0
    deg = np.rad2deg(TH)
    F = 1e-6 * np.cos(2 * TH)
    for q, hgt in ((0, 10e-6), (90, 6e-6), (180, 10e-6), (270, 6e-6)):
        d = s * ((deg - q + 180) % 360 - 180)
        F = F + hgt * np.exp(-0.5 * ((d - 8.0) / 2.0) ** 2)
    t = trace(0.15 + (R + F) * np.cos(TH), 0.15 + (R + F) * np.sin(TH), R, direction)
    heights = [g.height for g in glitches(t, lag_deg=30.0)]
    # + the undulation at the peak (8 deg past q) - its median over the arc before (25 deg
    # before q, the middle of 5..45 deg): at q = 0 +cos(16 deg) - cos(50 deg), at 90 -(...)
    u = 1e-6 * (np.cos(np.deg2rad(16.0)) - np.cos(np.deg2rad(50.0)))
    assert heights == pytest.approx([10e-6 + u, 6e-6 - u, 10e-6 + u, 6e-6 - u], abs=0.02e-6)
    assert [g.axis for g in glitches(t, 30.0)] == ["X", "Y", "X", "Y"]


def test_fit_circle_refuses_too_few_points() -> None:
    with pytest.raises(ValueError, match="length >= 3"):
        fit_circle([0.0, 1.0], [0.0, 1.0])


# ------------------------------------------------------------------ reference, table
def test_circle_path_is_on_the_circle_with_a_smooth_start_and_360_deg_at_feed() -> None:
    p = circle_path(0.01, 0.05, "cw", centre=(0.15, 0.14))
    r = np.hypot(p.x.x - 0.15, p.y.x - 0.14)
    assert np.max(np.abs(r - 0.01)) < 1e-15
    for ref in (p.x, p.y):  # v, a analytic = differences of x, v
        assert ref.v[0] == 0.0 and ref.a[0] == 0.0
        assert np.max(np.abs(np.gradient(ref.x, ref.Ts) - ref.v)[1:-1]) < 1e-5 * 0.05
        assert np.max(np.abs(np.gradient(ref.v, ref.Ts) - ref.a)[1:-1]) < 2e-3
    ev = slice(p.eval_start, p.eval_stop)
    speed = np.hypot(p.x.v, p.y.v)[ev]
    assert np.max(np.abs(speed - 0.05)) < 1e-12
    span = p.theta[p.eval_start] - p.theta[p.eval_stop - 1]  # cw: theta decreases
    assert 2 * np.pi - 2 * p.omega * p.x.Ts < span <= 2 * np.pi
    assert np.rad2deg(p.theta[p.eval_start]) == pytest.approx(45.0, abs=0.01)
    assert np.hypot(p.x.v[-1], p.y.v[-1]) == 0.0


def test_y_axis_defaults_and_magnet_shift() -> None:
    x, y = xy_axes()
    assert y.nominal["m"] == 40.0 and y.nominal["friction.F_s"] == pytest.approx(1.5 * 26.1)
    assert y.plant["m"] == pytest.approx(40.0 * sec4.PERTURBATION["m"])
    # a shift of a whole wavelength of every harmonic leaves the map; half of the first
    # harmonic's flips it
    p = x.nominal
    back = shift_magnets(p, 0.0375)
    assert all(back[k] == pytest.approx(p[k], abs=1e-12) for k in p if k.startswith("cogging."))
    half = shift_magnets(p, 0.0375 / 2)
    assert half["cogging.a[1]"] == pytest.approx(-p["cogging.a[1]"])
    assert half["cogging.a[2]"] == pytest.approx(p["cogging.a[2]"])


def test_master_of_four_fmus_equals_the_harness_per_axis() -> None:
    """Same sample convention: the X axis of the X-Y master is the harness's closed loop."""
    axes = xy_axes()
    p = circle_path(0.005, 0.05, "ccw")
    n = p.x.n
    res = simulate_axes(
        [
            AxisLoop(a.name, a.plant, controller_values(a, "gms"), ref)
            for a, ref in zip(axes, (p.x, p.y), strict=True)
        ]
    )
    for a, ref in zip(axes, (p.x, p.y), strict=True):
        spec = state_space_spec(
            {**a.nominal, "Ts": 5e-4}, feedforward=sec4.FeedforwardOptions(friction="gms")
        )
        with Plant(a.plant) as plant:
            h = simulate_closed_loop(plant, make_controller(spec, ref), n, float(ref.x[0]))
        assert np.max(np.abs(res[a.name]["x"] - h["x"])) < 1e-10, a.name


# ------------------------------------------------------------------ closed-loop circles
@pytest.fixture(scope="module")
def sec4_circles() -> dict:
    """The circle at Sec. 4's peak velocity and acceleration (r = 5 mm, one turn in 6 s) on
    two copies of the Sec. 4 axis, without and with GMS feedforward, both directions."""
    r = sec4.AMPLITUDE
    F = 2 * np.pi * r / sec4.PERIOD
    axes = identical_axes()
    return {ff: circular_case(axes, r, F, ff) for ff in ("none", "gms")}


def test_gms_feedforward_shrinks_the_quadrant_glitches_as_in_sec4(sec4_circles) -> None:
    none, gms = sec4_circles["none"], sec4_circles["gms"]
    g_none = [abs(g.height) for r in none.runs.values() for g in r.glitches]
    g_gms = [abs(g.height) for r in gms.runs.values() for g in r.glitches]
    # Sec. 4 (same axis, velocity, acceleration): 22.9 um without, 8.0 um with GMS FF
    assert 0.8 * 22.9e-6 < max(g_none) < 1.2 * 22.9e-6
    assert 0.7 * 8.0e-6 < max(g_gms) < 1.2 * 8.0e-6
    assert min(g_none) > 2 * max(g_gms)  # every glitch at least halved
    assert none.H > 2 * gms.H
    assert all(r.trace.G > 2 * gms.runs[d].trace.G for d, r in none.runs.items())


def test_identical_axes_give_mirror_symmetric_glitches(sec4_circles) -> None:
    """Mirrored about the diagonal, CCW becomes CW and X becomes Y: the glitch of CCW at
    theta equals CW's at 90 - theta, G_ccw = G_cw; all four within 15 % of each other."""
    for case in sec4_circles.values():
        ccw = {g.angle_deg: g.height for g in case.runs["ccw"].glitches}
        cw = {g.angle_deg: g.height for g in case.runs["cw"].glitches}
        for q in ccw:
            assert ccw[q] == pytest.approx(cw[(90.0 - q) % 360.0], abs=0.1e-6)
        assert case.runs["ccw"].trace.G == pytest.approx(case.runs["cw"].trace.G, abs=0.1e-6)
        h = np.array(list(ccw.values()))
        assert np.ptp(h) < 0.15 * np.max(np.abs(h))


def test_xy_system_runs_in_libcosim(tmp_path: Path) -> None:
    """The OSP form (4 FMUs, the controllers' internal generators, the first revolution the
    start transient): libcosim runs it; the master on the same system gives the ramped
    circle's G (the start is left out either way); libcosim's Jacobi delay (u one step of
    Ts/10 late) moves G by less than 40 % (measured +30 %)."""
    pytest.importorskip("libcosimpy", reason="libcosimpy: python/pyproject.toml [test]")
    axes = xy_axes()
    s = circle_system(axes, 0.01, 5 / 60, "ccw", "gms")
    xml = write_xy_osp(s, tmp_path / "osp")
    text = xml.read_text()
    assert text.count("<Simulator ") == 4 and text.count("<VariableConnection>") == 4
    xs, _ = run_libcosim_xy(tmp_path / "osp", s)
    xm = master_run(s)
    sl = s.eval_slice
    G_lc = trace(xs["X"][sl], xs["Y"][sl], 0.01).G
    G_m = trace(xm["X"][sl], xm["Y"][sl], 0.01).G
    ramped = run_circle(axes, 0.01, 5 / 60, "ccw", "gms").trace.G
    assert G_m == pytest.approx(ramped, abs=0.2e-6)
    assert abs(G_lc - G_m) < 0.4 * G_m


# ------------------------------------------------------------------ CLI
def _cli(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "feeddrive.cli", "circle", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_circle_command_prints_the_table_and_writes_the_report(tmp_path: Path) -> None:
    out = tmp_path / "circle"
    r = _cli("--radius-mm", "5", "--feed-m-min", "2", "--osp", "--out", str(out), cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[1].split()[:4] == ["r", "[mm]", "F", "[m/min]"]
    rows = {ln.split()[2]: ln.split() for ln in lines[2:4]}
    assert set(rows) == {"none", "gms"}
    G_none, G_gms = float(rows["none"][3]), float(rows["gms"][3])
    assert G_none > 2 * G_gms > 0
    assert (out / "index.html").is_file() and (out / ".feeddrive-output").is_file()
    assert {p.name for p in out.glob("circle_*.png")} == {
        "circle_r5mm_F2mmin_none.png",
        "circle_r5mm_F2mmin_gms.png",
    }
    assert "circular hysteresis" in (out / "index.html").read_text()
    assert sorted(p.parent.name for p in out.glob("osp/*/OspSystemStructure.xml")) == [
        f"circle_r5mm_F2mmin_{d}_{ff}" for d in ("ccw", "cw") for ff in ("gms", "none")
    ]


@pytest.mark.parametrize(
    "args, words",
    [
        (["--radius-mm", "160"], "radius 160 mm does not fit"),
        (["--x-model", "missing.json"], "missing.json"),
    ],
)
def test_circle_command_bad_input_is_one_line_exit_2(
    tmp_path: Path, monkeypatch, capsys, args, words
) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["circle", *args, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert words in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    "args", [["--radius-mm", "-1"], ["--direction", "up"], ["--feed-m-min", "x"]]
)
def test_circle_command_bad_option_exits_2(tmp_path: Path, capsys, args) -> None:
    with pytest.raises(SystemExit) as e:
        main(["circle", *args, "--out", str(tmp_path / "o")])
    assert e.value.code == 2 and "Traceback" not in capsys.readouterr().err


def test_circle_command_refuses_a_foreign_folder(tmp_path: Path, monkeypatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "o").mkdir()
    (tmp_path / "o" / "keep.txt").write_text("mine")
    assert main(["circle", "--radius-mm", "5", "--out", str(tmp_path / "o")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert (tmp_path / "o" / "keep.txt").read_text() == "mine"


# ------------------------------------------------------------------ study kind
STUDY = {
    "schema": "feeddrive.study/1",
    "name": "circle",
    "experiment": {
        "circle": {"radius": 0.005, "feed": 0.03, "feedforward": "none", "y_axis": "same"}
    },
    "parameters": {"friction.F_c": {"relative": 0.1}},
    "design": {"type": "oat"},
    "metrics": ["circular_deviation", "hysteresis", "max_glitch"],
}


def test_circle_study_rows_grow_with_the_friction_level(tmp_path: Path) -> None:
    """Without feedforward the reversal spike is the friction force over the servo's
    stiffness: G, H and the largest glitch grow with F_c (base -10 %, base, +10 %)."""
    study = parse_study(json.loads(json.dumps(STUDY)), "s.json", tmp_path)
    task = RunTask.of(study)
    rows = {r["label"]: r for r in (run_case(task, c) for c in cases(study))}
    assert all(r["status"] == "ok" for r in rows.values()), rows
    for col in ("G_m", "H_m", "max_glitch_m"):
        lo, base, hi = (rows[k][col] for k in ("friction.F_c=low", "base", "friction.F_c=high"))
        assert lo < base < hi, col
    assert 20e-6 < rows["base"]["max_glitch_m"] < rows["base"]["G_m"]


@pytest.mark.parametrize(
    "edit, field",
    [
        ({"metrics": ["reversal_error"]}, "metrics[0]"),
        (
            {"experiment": {"circle": {"radius": 0.005, "feed": 0.03, "directions": ["ccw"]}}},
            "experiment.circle.directions",
        ),
        ({"experiment": {"circle": {"radius": 0.2, "feed": 0.03}}}, "experiment.circle.radius"),
        (
            {"experiment": {"circle": {"radius": 0.005, "feed": 0.03, "feedforward": "magic"}}},
            "experiment.circle.feedforward",
        ),
    ],
)
def test_bad_circle_study_names_the_field(tmp_path: Path, edit, field) -> None:
    doc = {**STUDY, **edit}
    with pytest.raises(StudyError) as e:
        parse_study(doc, "s.json", tmp_path)
    assert e.value.field == field
