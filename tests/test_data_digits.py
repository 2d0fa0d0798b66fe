"""A recording's CSV carries the digits its signals have (feeddrive.data.RECORDING_DECIMALS):
positions to 1e-10 m, voltage and current to 1e-7, time on its sample grid; what is read back
lies within half a last digit of what was written."""

from __future__ import annotations

import numpy as np

from feeddrive.data import RECORDING_DECIMALS, Run, fixed_text, load_run, time_text, write_run


def test_fixed_text_is_short_and_has_no_negative_zero():
    assert fixed_text(np.array([0.16874989999999998, -4e-11, 2.5, 100.0, -1.23456789e-3]), 7) == [
        "0.1687499",
        "0",
        "2.5",
        "100",
        "-0.0012346",
    ]
    assert fixed_text(np.array([12.0, -0.4]), 0) == ["12", "0"]


def test_time_on_its_grid_else_every_digit():
    k = np.arange(200001)
    t = k * 0.0005  # 0.000500000000000056 and the like
    text = time_text(t)
    assert text[1] == "0.0005" and text[3] == "0.0015" and text[-1] == "100"
    assert np.array_equal(np.array(text, dtype=float), np.round(k * 5, 0) / 1e4)
    odd = np.cumsum(np.random.default_rng(3).uniform(1e-4, 2e-4, 50))  # no grid
    assert time_text(odd) == [repr(v) for v in odd.tolist()]


def test_recording_round_trip_within_half_a_digit_and_smaller(tmp_path):
    rng = np.random.default_rng(7)
    n = 20000
    t = np.arange(n) * 5e-4
    x = np.round((0.15 + 0.01 * np.sin(t)) / 1e-7) * 1e-7  # a 100 nm scale
    run = Run(
        time=t,
        u=rng.normal(0, 2, n),
        x=x,
        i=rng.normal(0, 0.5, n),
        x_ref=0.15 + 0.01 * np.sin(t),
        F_load=np.full(n, 54.9),
        meta={"Ts": 5e-4},
    )
    write_run(run, tmp_path / "exact.csv")
    write_run(run, tmp_path / "rec.csv", RECORDING_DECIMALS)
    back = load_run(tmp_path / "rec.csv")
    for name, step in (("x", 1e-10), ("x_ref", 1e-10), ("u", 1e-7), ("i", 1e-7), ("F_load", 1e-7)):
        err = np.max(np.abs(back.columns()[name] - run.columns()[name]))
        assert err <= 0.5 * step * (1 + 1e-6), (name, err)
    assert np.max(np.abs(back.x - run.x)) < 1e-15  # the scale's values are kept
    assert np.array_equal(back.time, np.round(np.arange(n) * 5.0) / 1e4)
    exact, rec = (tmp_path / "exact.csv").stat().st_size, (tmp_path / "rec.csv").stat().st_size
    assert rec < 0.7 * exact, (rec, exact)
