"""Tests of feeddrive.realdata.odrive: loaders and transforms on synthetic files, then the
numbers the analysis finds on the measured ODrive data (../shared/realdata/odrive-cogging).

Tolerances on measured numbers: the files are fixed, so the analysis is deterministic; the
tolerances say how far a *correct* method may move the number (grid, trimming, interpolation
choices) and are set from the data's own repeatability, not from the result:
- line amplitudes: 3 % -- trials a, b, d of the same sweep differ by up to 2.8 % (14/rev), and
  grids of 4..32 counts by up to 1.2 %; a wrong normalisation (factor 2) or grid (wrong step)
  is far outside;
- README values are rounded to 0.01 A: absolute 0.01 A;
- correlations: 0.02 -- the three 0.1 rev/s runs agree within 0.006, nocomp/comp within 0.01;
- velocity ripple std: 5 % -- trimming 0.5 s or 1 s of start transient moves it by up to 4 %.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from feeddrive.realdata import odrive as od

DATA = Path(__file__).resolve().parents[1].parent / "shared" / "realdata" / "odrive-cogging"
N = od.COUNTS_PER_REV


def _write_map(folder: Path, name: str, step: int, reverse: bool, f) -> Path:
    data = np.zeros(N)
    grid = od.map_grid(step, reverse)
    data[grid] = f(grid)
    path = folder / f"cogging_measure_final_{name}.npy"
    np.save(path, data)
    return path


def _cos(order: int, amp: float, phase: float):
    return lambda x: 0.3 + amp * np.cos(2 * np.pi * order * x / N + phase)


# ----------------------------------------------------------------------------- synthetic
def test_reverse_grid_is_offset():
    assert od.map_grid(16, False)[:2].tolist() == [0, 16]
    assert od.map_grid(16, True)[:3].tolist() == [15, 31, 47]
    assert od.map_grid(16, True)[-1] == N - 1
    with pytest.raises(ValueError, match="does not divide"):
        od.map_grid(24, False)


def test_loader_keeps_measured_entries_and_references_phase_to_count_zero(tmp_path):
    p = _write_map(tmp_path, "e_16r", 16, True, _cos(7, 0.8, 0.4))
    m = od.load_map(p)
    assert m.reverse and m.step == 16 and m.counts[0] == 15 and m.current.size == 512
    spec = od.revolution_spectrum(m)
    assert spec[0].real == pytest.approx(0.3, abs=1e-12)
    assert abs(spec[7]) == pytest.approx(0.8, abs=1e-12)
    assert np.angle(spec[7]) == pytest.approx(0.4, abs=1e-12)
    assert od.top_lines(spec, 1)[0].order == 7


@pytest.mark.parametrize(
    "bad, match",
    [
        (lambda d: d[:100], r"shape \(8192,\)"),
        (lambda d: np.where(np.arange(N) == 5, 1.0, d), "off the 16-count grid.*count 5"),
        (lambda d: np.where(np.arange(N) == 32, np.nan, d), "non-finite current at count 32"),
        (lambda d: np.where(np.arange(N) < 4096, 0.0, d), "sweep incomplete"),
    ],
)
def test_loader_names_file_and_problem(tmp_path, bad, match):
    p = _write_map(tmp_path, "a_16", 16, False, _cos(7, 0.8, 0.0))
    np.save(p, bad(np.load(p)))
    with pytest.raises(ValueError, match=match) as err:
        od.load_map(p)
    assert "cogging_measure_final_a_16.npy" in str(err.value)


def test_slow_run_loader_rejects_bad_files(tmp_path):
    p = tmp_path / "nocomp_0.npy"
    np.save(p, np.zeros((2, 500)))
    with pytest.raises(ValueError, match=r"nocomp_0\.npy.*shape"):
        od.load_slow_run(p)
    t = np.linspace(0, 1, 500)
    t[200] = t[199]
    np.save(p, np.vstack([t, t, t]))
    with pytest.raises(ValueError, match="time not increasing at sample 200"):
        od.load_slow_run(p)


@pytest.mark.parametrize("reverse", [False, True])
def test_dstft_of_constant_line_is_constant(reverse):
    """Demodulated rectangular-window DSTFT: a lone line reads its amplitude and phase at
    every position, even an order that is off-bin in a half-revolution window (7); orders an
    even number apart do not leak into each other (12 and the mean), odd ones do (7 and mean)."""
    counts = od.map_grid(16, reverse)
    s = od.position_stft(_cos(7, 0.5, -1.1)(counts) - 0.3, counts)
    assert s.centres.size == od.N_WINDOW_POSITIONS
    np.testing.assert_allclose(s.amplitude[7], 0.5 * np.exp(-1.1j), atol=1e-12)
    s = od.position_stft(_cos(12, 0.5, -1.1)(counts), counts)
    np.testing.assert_allclose(s.amplitude[12], 0.5 * np.exp(-1.1j), atol=1e-12)
    np.testing.assert_allclose(s.amplitude[0], 0.3, atol=1e-12)
    s = od.position_stft(_cos(7, 0.5, -1.1)(counts), counts)
    # 7/rev leaks into the local mean: +-0.5 sin(3.5 pi) / (3.5 pi) over half a revolution
    assert np.ptp(s.amplitude[0].real) == pytest.approx(1 / (3.5 * np.pi), rel=0.05)


def test_stationarity_flags_a_line_whose_amplitude_varies(tmp_path):
    """A 28/rev line whose amplitude varies +-60 % along the revolution is not periodic: over a
    half-revolution window the modulation averages to +-0.6*2/pi; a constant 7/rev line beside
    it is periodic, although the window leaks it into the 28/rev track (and vice versa)."""

    def f(x):
        return _cos(7, 0.9, 0.2)(x) + 0.5 * (1 + 0.6 * np.sin(2 * np.pi * x / N)) * np.cos(
            2 * np.pi * 28 * x / N
        )

    m = od.load_map(_write_map(tmp_path, "a_16", 16, False, f))
    s = od.stationarity(m, np.array([7, 28]), (7, 28))
    t7, t28 = s.tracks
    assert t7.periodic and t7.deviation < 1e-9
    assert not t28.periodic and t28.deviation == pytest.approx(0.6 * 2 / np.pi, rel=0.01)


def test_velocity_on_nonuniform_samples_is_exact_for_quadratic():
    t = np.cumsum(np.random.default_rng(0).uniform(1.5e-3, 4e-3, 400))
    x = 800 * t + 50 * t**2
    np.testing.assert_allclose(od.velocity(t, x)[1:-1], 800 + 100 * t[1:-1], rtol=1e-9)


# ----------------------------------------------------------------------------- measured data
@pytest.fixture(scope="module")
def findings():
    if not (DATA / od.MAP_FOLDER).is_dir():
        pytest.skip(
            f"measured ODrive data not found at {DATA} (expected ../shared beside the checkout)"
        )
    return od.analyse(DATA)


def test_forward_map_lines(findings):
    lines = findings.lines
    assert [ln.order for ln in lines] == [7, 28, 14, 36, 12]
    np.testing.assert_allclose(
        [ln.amplitude for ln in lines], [0.869, 0.565, 0.351, 0.294, 0.264], rtol=0.03
    )
    np.testing.assert_allclose(
        [ln.amplitude for ln in lines], [0.87, 0.56, 0.35, 0.29, 0.26], atol=0.01
    )  # README
    assert findings.grid_check < 0.03


def test_crosstalk_line_drops_without_neighbour(findings):
    assert findings.crosstalk_order == 7
    iso = {ln.order: ln.amplitude for ln in findings.isolated_lines}
    assert iso[7] == pytest.approx(0.26, abs=0.01)  # README
    for ln in findings.lines[1:]:  # 28, 14, 36, 12 stay (within the iso map's own smearing)
        assert iso[ln.order] == pytest.approx(ln.amplitude, rel=0.15)
    by_name = {t.name: t for t in findings.trials}
    assert by_name["b_16"].crosstalk.amplitude == pytest.approx(0.86, rel=0.03)
    assert by_name["c_16"].crosstalk.amplitude == pytest.approx(1.04, rel=0.03)


def test_trials_repeat_and_c_is_half_turn_like(findings):
    t = {x.name: x for x in findings.trials}
    assert t["b_16"].correlation > 0.99 and t["d_16"].correlation > 0.98
    assert t["c_16"].correlation < 0 and t["c_16"].correlation_half_turn > 0.98
    # the odd orders that are not multiples of 7 keep their phase in c: no real half-turn shift
    assert t["c_16"].odd_coherence > 0.3
    assert t["b_16"].rms_difference == pytest.approx(0.043, abs=0.005)


def test_dstft_periodic_and_not(findings):
    st = {s.map_name: s for s in findings.stationarity}
    for name in ("a_16", "b_16", "c_16", "d_16", "e_16r"):
        assert all(t.periodic for t in st[name].tracks), name
        assert st[name].local_mean_drift < 0.03, name  # zero-frequency term does not drift
    a = st["a_16"]
    assert a.local_mean_range[1] - a.local_mean_range[0] > 0.1  # ... though raw DSTFT DC moves
    iso = {t.order: t for t in st["iso_16"].tracks}
    assert not iso[84].periodic and not iso[28].periodic
    assert st["rev_16"].local_mean_drift > 0.15  # the rev_16 sweep drifts


def test_friction_from_forward_reverse(findings):
    fr = findings.friction
    assert (fr.forward, fr.reverse) == ("c_16", "e_16r")
    assert fr.mean_difference == pytest.approx(0.34, abs=0.01)  # README
    assert 0.30 < fr.pair_means[0] and fr.pair_means[2] < 0.42
    assert fr.difference_std < 0.5 * fr.mean_difference  # mostly constant
    assert {ln.order for ln in fr.difference_lines[:2]} == {28, 36}
    assert 5 < fr.offset_counts < 10 and fr.offset_r2 > 0.4
    # what the offset leaves is white point noise (no position dependence left)
    assert fr.residual_std == pytest.approx(fr.noise_std, rel=0.15)


def test_slow_runs_correlation_and_ripple(findings):
    s = od.slow_summary(findings)
    fast_n, fast_c = s["slow2/nocomp"], s["slow2/comp"]
    slow_n, slow_c = s["slow2_slower/nocomp"], s["slow2_slower/comp"]
    assert fast_n["speed"] == pytest.approx(0.1, rel=0.02)
    assert slow_n["speed"] == pytest.approx(0.03, rel=0.02)
    assert fast_n["r_static"] == pytest.approx(0.79, abs=0.02)  # README 0.81
    assert slow_n["r_static"] == pytest.approx(0.933, abs=0.02)  # README 0.94
    assert slow_c["r_static"] == pytest.approx(0.942, abs=0.02)
    for g in (fast_n, fast_c, slow_n, slow_c):  # same lag at both speeds: Iq filter
        assert g["r_lagged"] > 0.98 and 0.08 < g["lag_s"] < 0.12
        assert g["r_lagged_no_crosstalk"] < 0.7
    for k in ("slow2_slower/crosstalk_nocomp", "slow2_slower/crosstalk_comp"):
        assert s[k]["r_lagged_no_crosstalk"] > 0.8 > s[k]["r_lagged"] + 0.4
    assert fast_n["velocity_std"] == pytest.approx(769, rel=0.05)  # README 714
    assert fast_c["velocity_std"] == pytest.approx(302, rel=0.05)  # README 297
    assert slow_n["velocity_std"] == pytest.approx(289, rel=0.05)  # README 270
    assert slow_c["velocity_std"] == pytest.approx(164, rel=0.05)  # README 163


def test_report_text(findings):
    text = od.findings_text(findings)
    assert "7/rev line drops 0.87 -> 0.26 A" in text
    assert "forward - reverse = 0.343 A" in text
    assert "NOT periodic" in text
