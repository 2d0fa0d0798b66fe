"""Stick/slip events in model exchange (CVode root finding through fmpy).

* Sinusoidal motion: each reversal sticks every element once and each slips once again
  (stats.n_stick and stats.n_slip grow by N = 5 per reversal, nothing else).
* Stage at rest, all elements stuck, ringing in the ~54 Hz mode: the velocity crosses zero
  twice per period, yet no state event happens (no indicator watches v while all stick).
"""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np
import pytest

from feeddrive.physics.position_maps import cogging
from fmu_loops import PositionLoop, me_plant, run_law

pytestmark = pytest.mark.usefixtures("fmu_path")

X0 = 0.15


def test_each_reversal_sticks_and_slips_every_element_once(paper: dict) -> None:
    """Position loop on the paper model (cogging on, u = 0, F_ext drives): x = x0 + 1 mm
    sin(2 pi 2 t), started moving at the sine's speed with virgin elements, for 1.3 s
    (5 reversals)."""
    X, w = 1e-3, 2 * np.pi * 2.0

    def ref(t: float) -> tuple[float, float, float]:
        return X0 + X * np.sin(w * t), X * w * np.cos(w * t), -X * w * w * np.sin(w * t)

    plant = me_plant({"effects.current_dynamics": False})
    try:
        run = run_law(
            plant,
            2e-3,
            650,
            PositionLoop(ref, paper["m"]),
            {"x": X0, "v": X * w},
            integers=("n_stuck", "stats.n_stick", "stats.n_slip"),
        )
    finally:
        plant.close()
    v, t = run["v"], run["time"]
    assert np.max(np.abs(run["x"] - [ref(tk)[0] for tk in t])) < 2e-5  # it followed
    rev = np.nonzero(np.sign(v[1:]) != np.sign(v[:-1]))[0]  # v sign changes
    assert len(rev) == 5
    t_rev_ref = (np.arange(5) + 0.5) / 4.0  # reference reversals at 0.125, 0.375, ...
    assert np.allclose(t[rev], t_rev_ref, atol=0.01)
    stick, slip = run["stats.n_stick"], run["stats.n_slip"]
    # between reversals: the counts near the speed maxima of each half period (the first
    # at 50 ms, after the virgin elements broke away: Delta_5 / 12.6 mm/s = 9 ms)
    mids = [int(round(tk / 2e-3)) for tk in [0.05, 0.25, 0.5, 0.75, 1.0, 1.25]]
    assert list(np.diff(stick[mids])) == [5] * 5
    assert list(np.diff(slip[mids])) == [5] * 5
    assert slip[mids[0]] == 5 and stick[mids[0]] == 0  # start: the 5 virgin elements broke
    assert run.stats["stats.n_stick"] == 25 and run.stats["stats.n_slip"] == 30
    # one event for the sticking of all five, one per element slipping again
    assert run.state_events == 5 + 5 * (1 + 5)


def _ringing_expectation(paper: dict) -> tuple[float, float]:
    """F_cg(x0) and the expected frequency sqrt((sum k_i + dF_cg/dx) / m) / 2 pi [Hz]."""
    h = 1e-6
    slope = float(cogging(X0 + h, paper) - cogging(X0 - h, paper)) / (2 * h)  # 3.6e3 N/m
    ksum = sum(paper[f"friction.k[{j}]"] for j in range(1, 6))  # 1.84e6 N/m
    return float(cogging(X0, paper)), float(np.sqrt((ksum + slope) / paper["m"]) / (2 * np.pi))


def _frequency(t: np.ndarray, x: np.ndarray) -> float:
    d = x - x.mean()
    i = np.nonzero((d[:-1] < 0) & (d[1:] >= 0))[0]
    tc = t[i] - d[i] * (t[i + 1] - t[i]) / (d[i + 1] - d[i])
    return (len(tc) - 1) / (tc[-1] - tc[0])


def test_ringing_at_rest_has_no_state_events(paper: dict) -> None:
    """v0 = 0.1 mm/s kick, cogging balanced by F_ext: amplitude 0.3 um, element forces
    < 0.4 N << nu_i F_s, so nothing may switch.  Paper model, current loop on (a time
    event every 0.5 ms), 0.5 s = 27 periods."""
    F_cg0, f_exp = _ringing_expectation(paper)
    assert 53.8 < f_exp < 54.0  # MODEL.md: sqrt(sum k / m) / 2 pi = 54 Hz
    plant = me_plant({})
    try:
        run = run_law(plant, 5e-4, 1000, None, {"x": X0, "v": 1e-4, "F_ext": -F_cg0})
    finally:
        plant.close()
    assert run.state_events == 0
    assert run.stats["stats.n_state_events"] == 0
    assert run.stats["stats.n_stick"] == 0 and run.stats["stats.n_slip"] == 0
    assert np.all(run["n_stuck"] == 5)
    assert run.time_events == 999  # the samples, nothing else
    v = run["v"]
    assert np.sum(np.sign(v[1:]) != np.sign(v[:-1])) >= 50  # it did ring through zero
    assert _frequency(run["time"], run["x"]) == pytest.approx(f_exp, rel=1e-3)


def test_ringing_with_fmpy_simulate_fmu(fmu_path: Path, paper: dict) -> None:
    """The same through fmpy.simulate_fmu (ME, CVode, record_events): every event instant is
    recorded twice; the only events must be the current-loop samples k Ts."""
    F_cg0, f_exp = _ringing_expectation(paper)
    res = fmpy.simulate_fmu(
        str(fmu_path),
        fmi_type="ModelExchange",
        solver="CVode",
        stop_time=0.25,
        output_interval=5e-4,
        relative_tolerance=1e-8,
        record_events=True,
        output=["x", "v", "n_stuck"],
        start_values={"x": X0, "v": 1e-4, "F_ext": -F_cg0},
    )
    t = res["time"]
    ev = t[1:][np.diff(t) == 0]
    k = ev / 5e-4
    assert np.allclose(k, np.round(k), atol=1e-6), "an event off the sample grid (state event)"
    assert len(ev) == 500
    assert np.all(res["n_stuck"] == 5)
    keep = np.concatenate([[True], np.diff(t) > 0])
    assert _frequency(t[keep], res["x"][keep]) == pytest.approx(f_exp, rel=2e-3)
