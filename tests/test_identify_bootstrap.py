"""Identification bootstrap (feeddrive.identify.bootstrap, feeddrive.study.bootstrap).

A reduced campaign (PRBS, the loaded whole-stroke map runs, six Stribeck speeds, the
open-loop force run) on the perturbed truth of test_identify_roundtrip, every run repeated
three times with its own noise seed.  Statistics behind the assertions:

- coverage (at the campaign's default sensor noise): a bootstrap interval describes the noise
  spread of the estimator around its expectation; the pipeline's own deterministic error (its
  estimate from noise-free runs minus the truth, ``b``) is not noise and is added to the
  interval on both sides:
  lo - |b| <= truth <= hi + |b| for the well-determined parameters.  (At 4x the noise
  F_c moves by a noise-induced +0.015 N, the noise being a force on the stage: a bias of
  the estimator at that noise, which no resampling of that campaign can show);
- width: the runs at 4x the current noise and 4x the scale quantum give 4x the
  noise-driven spread; the percentile width from 8 replicates is off by well under a
  factor 2, so the low-noise width must be smaller for every one of them.
"""

from __future__ import annotations

import json
from dataclasses import replace
from functools import partial

import pytest

from feeddrive import cli
from feeddrive.data import write_run
from feeddrive.experiments.constant_speed import PAPER_LOADS, constant_speed_runs, stribeck_runs
from feeddrive.experiments.force_open_loop import force_open_loop_runs
from feeddrive.experiments.prbs import prbs_runs
from feeddrive.experiments.recording import run_seed
from feeddrive.harness.sensors import Sensors
from feeddrive.identify.bootstrap import BootstrapTask, cells, check_campaign, run_replicates
from feeddrive.identify.pipeline import identify_runs
from feeddrive.model_file import ModelFileError, load_model, paper_model, save_model
from feeddrive.report.identification import add_to_page, uncertainty_rows
from feeddrive.report.page import Page
from feeddrive.study.bootstrap import run_bootstrap
from test_identify_roundtrip import truth_model

#: The mass is fitted to one open-loop run per replicate but with the maps and the friction of
#: the other (resampled) steps, so it varies with every resample.  The current loop is fitted
#: to one PRBS run alone: at most REPEATS values over the replicates, refused (SINGLE_RUN).
WELL_DETERMINED = ("m", "friction.F_s", "friction.F_c", "friction.sigma2")
SINGLE_RUN = ("current.a[1]", "current.b[2]")
SPEEDS = (0.5e-3, 1e-3, 2e-3, 8e-3, 30e-3, 120e-3)
REPEATS = 3


def jobs():
    yield "prbs", partial(prbs_runs, periods=1)
    yield (
        "maps",
        partial(constant_speed_runs, speeds=(20e-3,), loads=PAPER_LOADS, segment=(0.001, 0.299)),
    )
    yield "stribeck", partial(stribeck_runs, speeds=SPEEDS, cruise_time=1.0, min_length=3e-3)
    yield "force", partial(force_open_loop_runs, n_periods=5)


def campaign(scale: float, repeats: int):
    params = truth_model().fmu_parameters()
    out = []
    for k in range(repeats):
        for label, fn in jobs():
            s = Sensors(seed=run_seed(7 + 1000 * k, label))
            s = replace(s, current_noise=s.current_noise * scale, quantum=s.quantum * scale)
            out += fn(params, s)
    return out


@pytest.fixture(scope="module")
def noisy(fmu_path):
    return campaign(4.0, REPEATS)


@pytest.fixture(scope="module")
def quiet(fmu_path):
    return campaign(1.0, REPEATS)


def _boot(runs, **kw):
    base = identify_runs(runs)
    return base, run_bootstrap(runs, base.model, base.defaulted, 8, seed=3, **kw)


def test_uncertainty_round_trip_and_rules(tmp_path):
    m = replace(
        paper_model(), uncertainty={"m": {"lo": 16.0, "hi": 16.3, "level": 0.95, "replicates": 20}}
    )
    save_model(m, tmp_path / "m.json")
    back = load_model(tmp_path / "m.json")
    assert back.uncertainty == m.uncertainty and back == m
    doc = json.loads((tmp_path / "m.json").read_text())
    for bad, key in (
        (({"nope": {"lo": 0, "hi": 1, "level": 0.9, "replicates": 2}}), "nope"),
        ({"m": {"lo": 2.0, "hi": 1.0, "level": 0.9, "replicates": 2}}, "hi"),
        ({"m": {"lo": 1.0, "hi": float("inf"), "level": 0.9, "replicates": 2}}, "hi"),
        ({"m": {"lo": 1.0, "hi": 2.0, "level": 1.5, "replicates": 2}}, "level"),
        ({"m": {"lo": 1.0, "hi": 2.0, "level": 0.9}}, "replicates"),
    ):
        doc["uncertainty"] = bad
        (tmp_path / "bad.json").write_text(json.dumps(doc))
        with pytest.raises(ModelFileError, match=key):
            load_model(tmp_path / "bad.json")
    assert "uncertainty" not in json.loads(
        (save_model(paper_model(), tmp_path / "p.json") or tmp_path / "p.json").read_text()
    )


@pytest.mark.parametrize(
    "args",
    (
        ["--bootstrap", "1"],
        ["--bootstrap", "x"],
        ["--bootstrap", "4", "--level", "1.5"],
        ["--bootstrap", "4", "--workers", "0"],
        ["--bootstrap", "4", "--seed", "-1"],
        ["--bootstrap", "12", "--interval-method", "guess"],
    ),
)
def test_bad_bootstrap_arguments_exit_2(tmp_path, capsys, args):
    with pytest.raises(SystemExit) as e:
        cli.main(["identify", str(tmp_path), "--out", str(tmp_path / "m.json"), *args])
    assert e.value.code == 2
    assert "error:" in capsys.readouterr().err


@pytest.mark.slow
def test_campaign_without_repeats_is_refused_with_one_line(tmp_path, quiet, capsys):
    one = [
        r for r in quiet if r.meta["sensors"]["seed"] in {run_seed(7, label) for label, _ in jobs()}
    ]
    with pytest.raises(ValueError, match="repeats"):
        check_campaign(one)
    for r in one:
        write_run(r, tmp_path / f"{r.meta['name']}.csv")
    assert (
        cli.main(
            [
                "identify",
                str(tmp_path),
                "--out",
                str(tmp_path / "m.json"),
                "--bootstrap",
                "4",
                "--interval-method",
                "runs",
                "--serial",
            ]
        )
        == 2
    )
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "repeats" in err
    assert not (tmp_path / "m.json").exists()


@pytest.mark.slow
def test_bootstrap_covers_the_truth_and_shrinks_with_noise(noisy, quiet, fmu_path):
    truth = truth_model().parameters
    assert sorted(len(c) for c in cells(noisy)) == [REPEATS] * (len(noisy) // REPEATS)
    exact = identify_runs(campaign(0.0, 1)).model.parameters  # the method's own error
    _base_n, boot_n = _boot(noisy, workers=2)
    _, boot_q = _boot(quiet, parallel=False)
    assert boot_n.failed == 0 and boot_q.failed == 0, boot_n.text() + boot_q.text()
    for n in SINGLE_RUN:
        assert n in boot_n.refused and n not in boot_n.uncertainty, boot_n.text()
    lines = []
    for n in WELL_DETERMINED:
        b = abs(exact[n] - truth[n])
        iv, iq = boot_n.uncertainty[n], boot_q.uncertainty[n]
        lines.append(
            f"{n}: truth {truth[n]:.6g} bias {b:.3g} default noise [{iq['lo']:.6g}, "
            f"{iq['hi']:.6g}] 4x noise [{iv['lo']:.6g}, {iv['hi']:.6g}]"
        )
        assert iq["lo"] - b <= truth[n] <= iq["hi"] + b, "\n".join(lines)
        assert iq["hi"] - iq["lo"] < iv["hi"] - iv["lo"], "\n".join(lines)
    print("\n".join(lines))
    # the same replicates in this process: the same resample (seed per replicate).  Not
    # bitwise: Dask's workers run BLAS single-threaded, this process multi-threaded (a
    # 1e-9 relative rounding difference); another resample differs by ~1e-4.
    task = BootstrapTask(
        tuple(noisy), tuple(tuple(c) for c in cells(noisy)), tuple(boot_n.uncertainty), 3
    )
    again = run_replicates(task, [0, 5])
    for r in again:
        ref = boot_n.rows[r["replicate"]]
        for k in WELL_DETERMINED:
            assert r[k] == pytest.approx(ref[k], rel=1e-7, abs=0), k


@pytest.mark.slow
def test_report_shows_the_intervals(quiet, tmp_path):
    runs = quiet[: len(quiet) // REPEATS * 2]  # two repeats: a cheaper bootstrap
    base = identify_runs(runs, truth=truth_model())
    boot = run_bootstrap(runs, base.model, base.defaulted, 3, parallel=False)
    base.model = replace(base.model, uncertainty=boot.uncertainty)
    rows = {r["parameter"]: r for r in uncertainty_rows(base)}
    F = "friction.F_s"
    assert set(WELL_DETERMINED) <= set(rows) and rows[F]["replicates"] == 3
    assert rows[F]["lo"] <= rows[F]["hi"] and rows[F]["true"] == truth_model().parameters[F]
    assert rows[F]["method"] == "runs, percentile"
    assert not any(n.startswith("current.") for n in rows) and "Ts" not in rows
    page = Page(tmp_path, "identification")
    add_to_page(page, base)
    html = page.write().read_text()
    assert "bootstrap intervals" in html and "true inside" in html
    assert "noise spread only, without the method" in html


@pytest.mark.slow
def test_bootstrap_study_file_through_sweep(quiet, tmp_path, capsys):
    """``"kind": "bootstrap"`` in a study file: `feeddrive sweep` identifies the folder,
    bootstraps it and writes model.json (with its intervals), replicates.csv/.parquet (one row
    per replicate, the same numbers as run_bootstrap with the same seed: a replicate depends on
    (seed, r) only) and the report; a bad field or --resume is one line and exit 2."""
    import pyarrow.parquet as pq

    runs = quiet[: len(quiet) // REPEATS * 2]
    folder = tmp_path / "campaign"
    folder.mkdir()
    for j, r in enumerate(runs):
        write_run(r, folder / f"{j:03d}_{r.name}.csv")
    study = {
        "schema": "feeddrive.study/1",
        "kind": "bootstrap",
        "name": "intervals",
        "runs": "campaign",
        "replicates": 3,
        "seed": 3,
        "method": "runs",
    }
    (tmp_path / "boot.json").write_text(json.dumps(study))
    out = tmp_path / "out"
    assert (
        cli.main(
            ["sweep", str(tmp_path / "boot.json"), "--out", str(out), "--serial", "--no-progress"]
        )
        == 0
    )
    text = capsys.readouterr().out
    assert "study intervals, bootstrap: 3/3 replicates" in text and "friction.F_s" in text
    model = load_model(out / "model.json")
    assert set(WELL_DETERMINED) <= set(model.uncertainty)
    assert all(model.uncertainty[k]["replicates"] == 3 for k in WELL_DETERMINED)
    table = pq.read_table(out / "replicates.parquet").to_pydict()
    base = identify_runs(runs)
    ref = run_bootstrap(runs, base.model, base.defaulted, 3, seed=3, parallel=False)
    assert table["replicate"] == [0, 1, 2] and table["status"] == ["ok"] * 3
    for k in WELL_DETERMINED:
        assert table[k] == [r[k] for r in ref.rows], k
    assert (out / "replicates.csv").read_text().count("\n") == 4
    assert "bootstrap intervals" in (out / "report.html").read_text()
    for bad, fld in (
        ({"replicates": 1}, "replicates"),
        ({"runs": "nowhere"}, "runs"),
        ({"kind": "bogus"}, "kind"),
        ({"level": 2}, "level"),
        ({"extra": 1}, "extra"),
        ({"method": "guess"}, "method"),
    ):
        (tmp_path / "bad.json").write_text(json.dumps({**study, **bad}))
        assert cli.main(["sweep", str(tmp_path / "bad.json"), "--out", str(tmp_path / "o2")]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and f"field {fld}" in err[0], err
    assert cli.main(["sweep", str(tmp_path / "boot.json"), "--out", str(out), "--resume"]) == 2
    assert "--resume" in capsys.readouterr().err and load_model(out / "model.json") == model
