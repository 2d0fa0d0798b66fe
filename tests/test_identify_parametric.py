"""Parametric bootstrap of the identification (feeddrive.identify.parametric,
feeddrive.experiments.resimulate): the interval arithmetic and its refusals on synthetic
replicates, a run made again on its own plant with its own noise seed, and the command's
refusals (one line, exit 2).

The interval of a normal estimator with bias b and spread s, from B replicates, is
theta_hat - b +- t_{B-1} s sqrt(1 + 1/B): the synthetic rows below have a known mean and
standard deviation, so the end points are known to rounding.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest
from scipy import stats

from feeddrive import cli
from feeddrive.data import write_run
from feeddrive.experiments.constant_speed import constant_speed_runs
from feeddrive.experiments.force_open_loop import force_open_loop_runs
from feeddrive.experiments.prbs import prbs_runs
from feeddrive.experiments.resimulate import can_resimulate, resimulate
from feeddrive.harness.sensors import Sensors
from feeddrive.identify.parametric import (
    FAILED,
    MIN_REPLICATES,
    OK,
    STRUCTURE_SHARE,
    bias_corrected,
)
from feeddrive.model_file import ModelFileError, load_model, paper_model, save_model
from feeddrive.study.coverage import coverage_truth, lowest_count


def _rows(
    values: dict[str, list[float]], structure: list[str] | None = None, failed: int = 0
) -> list[dict]:
    n = len(next(iter(values.values())))
    rows = [
        {
            "replicate": r,
            **{k: v[r] for k, v in values.items()},
            "structure": structure[r] if structure else "2/2",
            "status": OK,
            "message": "",
        }
        for r in range(n)
    ]
    rows += [
        {
            "replicate": n + j,
            **dict.fromkeys(values, math.nan),
            "structure": "",
            "status": FAILED,
            "message": "x",
        }
        for j in range(failed)
    ]
    return rows


def test_bias_corrected_interval_arithmetic():
    rng = np.random.default_rng(1)
    v = 10.0 + 0.3 + 0.05 * rng.standard_normal(20)  # estimate 10, bias about +0.3
    iv = bias_corrected({"m": 10.0}, _rows({"m": list(v)}), ["m"], 0.95)
    B, s = 20, float(np.std(v, ddof=1))
    half = stats.t.ppf(0.975, B - 1) * s * math.sqrt(1 + 1 / B)
    centre = 10.0 - (np.mean(v) - 10.0)
    got = iv.uncertainty["m"]
    assert got["lo"] == pytest.approx(centre - half, rel=1e-12)
    assert got["hi"] == pytest.approx(centre + half, rel=1e-12)
    assert got["bias"] == pytest.approx(np.mean(v) - 10.0, rel=1e-12)
    assert got["replicates"] == 20 and got["method"] == "parametric"
    assert iv.evidence["m"]["spread"] == pytest.approx(s)
    # the bias moves the interval below the estimate: the estimate is outside it here
    assert got["hi"] < 10.0


def test_refusals_say_why():
    v = list(np.linspace(1.0, 1.1, MIN_REPLICATES - 1))
    few = bias_corrected({"m": 1.0}, _rows({"m": v}), ["m"], 0.95)
    assert not few.uncertainty and "simulated campaigns identified" in few.refused["m"]
    v = list(np.linspace(1.0, 1.1, 12))
    failing = bias_corrected({"m": 1.0}, _rows({"m": v}, failed=2), ["m"], 0.95)
    assert not failing.uncertainty and "failed" in failing.refused["m"]
    same = bias_corrected({"Ts": 5e-4}, _rows({"Ts": [5e-4] * 12}), ["Ts"], 0.95)
    assert same.fixed == ["Ts"] and not same.refused and not same.uncertainty
    # the current loop's coefficients: from the replicates of the estimate's structure when
    # they are at least STRUCTURE_SHARE of them, else refused
    n_other = int(12 * (1 - STRUCTURE_SHARE)) + 1
    structures = ["2/2"] * (12 - n_other) + ["3/2"] * n_other
    vals = {"current.a[1]": list(np.linspace(1.3, 1.5, 12)), "m": v}
    mixed = bias_corrected(
        {"current.a[1]": 1.4, "m": 1.0}, _rows(vals, structures), list(vals), 0.95, structure="2/2"
    )
    assert "current.a[1]" in mixed.refused and "3/2" in mixed.refused["current.a[1]"]
    assert "m" in mixed.uncertainty  # other steps are not affected
    structures = ["2/2"] * 11 + ["3/2"]
    vals["current.a[1]"][-1] = 99.0  # another structure's coefficient
    one_off = bias_corrected(
        {"current.a[1]": 1.4, "m": 1.0}, _rows(vals, structures), list(vals), 0.95, structure="2/2"
    )
    assert one_off.uncertainty["current.a[1]"]["replicates"] == 11
    assert one_off.uncertainty["current.a[1]"]["hi"] < 2.0


def test_lowest_count_is_the_binomial_one_percent_quantile():
    for K in (8, 20, 50):
        c = lowest_count(K)
        assert stats.binom.cdf(c, K, 0.95) >= 0.01 > stats.binom.cdf(c - 1, K, 0.95)
    assert lowest_count(20) == 16 and lowest_count(8) == 6


def test_model_file_keeps_method_and_bias(tmp_path):
    iv = {
        "lo": 16.0,
        "hi": 16.3,
        "level": 0.95,
        "replicates": 20,
        "method": "parametric",
        "bias": -0.01,
    }
    m = replace(paper_model(), uncertainty={"m": iv})
    save_model(m, tmp_path / "m.json")
    assert load_model(tmp_path / "m.json").uncertainty == {"m": iv}
    doc = json.loads((tmp_path / "m.json").read_text())
    for bad, key in (
        ({**iv, "method": "guess"}, "method"),
        ({**iv, "bias": "x"}, "bias"),
        ({**iv, "spread": 1.0}, "spread"),
    ):
        doc["uncertainty"] = {"m": bad}
        (tmp_path / "bad.json").write_text(json.dumps(doc))
        with pytest.raises(ModelFileError, match=key):
            load_model(tmp_path / "bad.json")


def test_a_run_made_again_on_its_plant_with_its_seed_is_the_run(fmu_path):
    """PRBS (closed loop, held position, the sequence from the sidecar) and the open-loop
    force run: the same plant and the same noise seed give the recorded run back (to the
    solver's rounding); another seed gives other noise of the same rms."""
    params = coverage_truth().fmu_parameters()
    for run in (
        prbs_runs(params, Sensors(seed=5), periods=1)[0],
        force_open_loop_runs(params, Sensors(seed=6), n_periods=2)[0],
    ):
        assert can_resimulate(run) is None
        sensors = Sensors.from_json(run.meta["sensors"])
        again = resimulate(run, params, sensors)
        assert again.n == run.n and again.meta["kind"] == run.meta["kind"]
        np.testing.assert_allclose(again.u, run.u, atol=1e-9)
        np.testing.assert_allclose(again.x, run.x, atol=1e-9)
        np.testing.assert_allclose(again.i, run.i, atol=1e-9)
        other = resimulate(run, params, replace(sensors, seed=99))
        d = other.i - run.i
        assert np.std(d) == pytest.approx(np.sqrt(2) * sensors.current_noise, rel=0.15)


def test_runs_that_cannot_be_made_again_give_no_interval_and_say_why(fmu_path, tmp_path, capsys):
    """A PRBS run without its controller or sequence has its current made again from its
    recorded u (Eq. 2: i = G(z) u; noise-free, the FMU's current to 1 uA after the
    filter's start); a closed-loop run without its controller cannot be made again: the
    model is identified and written without intervals, and the output says why.  Fewer
    than 10 replicates are refused (one line, exit 2)."""
    params = paper_model().fmu_parameters()
    quiet = Sensors(current_noise=0.0, seed=5)
    run = prbs_runs(params, quiet, periods=1)[0]
    no_ctrl = replace(run, meta={**run.meta, "controller": None})
    assert "controller" in can_resimulate(no_ctrl)
    no_seq = replace(run, meta={k: v for k, v in run.meta.items() if k != "prbs_start"})
    assert "prbs_start" in can_resimulate(no_seq)
    again = resimulate(no_seq, params, quiet, current_only=True)
    np.testing.assert_array_equal(again.u, run.u)
    np.testing.assert_allclose(again.i[50:], run.i[50:], atol=1e-6)
    cv = constant_speed_runs(
        params,
        Sensors(seed=6),
        speeds=(20e-3,),
        loads=(0.0,),
        directions=(1,),
        segment=(0.14, 0.16),
    )[0]
    cv = replace(cv, meta={**cv.meta, "controller": None})
    folder = tmp_path / "runs"
    folder.mkdir()
    for r in (
        replace(prbs_runs(params, Sensors(seed=7), periods=1)[0], meta=no_ctrl.meta),
        force_open_loop_runs(params, Sensors(seed=8), n_periods=2)[0],
        cv,
    ):
        write_run(r, folder / f"{r.meta['name']}.csv")
    out = tmp_path / "m.json"
    assert (
        cli.main(
            [
                "identify",
                str(folder),
                "--out",
                str(out),
                "--bootstrap",
                "12",
                "--serial",
                "--no-progress",
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    assert "not run, no intervals" in text and "controller" in text, text
    assert load_model(out).uncertainty == {}
    out.unlink()
    assert (
        cli.main(["identify", str(folder), "--out", str(out), "--bootstrap", "4", "--serial"]) == 2
    )
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "at least 10" in err and not out.exists()


@pytest.mark.slow
def test_identify_bootstrap_writes_bias_corrected_intervals_and_the_report_shows_them(
    fmu_path, tmp_path, capsys
):
    """``identify DIR --bootstrap 10`` on a campaign made by the FMU: the model file's
    intervals say parametric and carry the bias; the summary names the measured noise (the
    campaign's 5 mA within 10 %); the report's table shows method, replicates and bias."""
    from feeddrive.identify.pipeline import identify_runs
    from feeddrive.report.identification import add_to_page, uncertainty_rows
    from feeddrive.report.page import Page
    from feeddrive.study.coverage import coverage_campaign

    runs = coverage_campaign(3, repeats=1)
    (tmp_path / "runs").mkdir()
    for r in runs:
        write_run(r, tmp_path / "runs" / f"{r.name}.csv")
    save_model(coverage_truth(), tmp_path / "truth.json")
    out = tmp_path / "m.json"
    assert (
        cli.main(
            [
                "identify",
                str(tmp_path / "runs"),
                "--out",
                str(out),
                "--bootstrap",
                "10",
                "--serial",
                "--no-progress",
                "--truth",
                str(tmp_path / "truth.json"),
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    assert "parametric bootstrap: 10/10 campaigns" in text, text
    noise = float(text.split("current noise ")[1].split(" mA")[0])
    assert noise == pytest.approx(5.0, rel=0.1)
    model = load_model(out)
    for n in ("m", "friction.F_s", "friction.sigma2"):
        iv = model.uncertainty[n]
        assert iv["method"] == "parametric" and iv["replicates"] == 10 and "bias" in iv
        assert iv["lo"] < iv["hi"]
    assert "Ts" not in model.uncertainty
    res = identify_runs(runs, truth=coverage_truth())
    res.model = model
    rows = {r["parameter"]: r for r in uncertainty_rows(res)}
    assert rows["friction.F_s"]["method"] == "parametric, bias-corrected"
    assert rows["friction.F_s"]["bias corrected"] == model.uncertainty["friction.F_s"]["bias"]
    page = Page(tmp_path / "report", "identification")
    add_to_page(page, res)
    html = page.write().read_text()
    assert "parametric, bias-corrected" in html and "intervals.md" in html
