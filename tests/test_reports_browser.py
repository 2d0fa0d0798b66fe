"""Every HTML page the tool writes, opened in headless Chromium: the main job's report
(`run`), the identification report (`report`), the diagnosis (`diagnose`), a study's report
(`sweep`) and the circular test (`circle`), each made by its command on a small input.

Checks on each page: no console error (a failed image load is one), every image loaded
(``naturalWidth > 0``), nothing wider than a 1280 px viewport (``scrollWidth <= 1280``).
A full-page screenshot of each is kept under ``build/screenshots/``.

Needs Debian's ``chromium`` and ``chromium-driver`` (``make browser`` installs them where it
can: as root with apt-get) and selenium (the ``test`` extra); skipped with the reason otherwise.
"""

from __future__ import annotations

import base64
import json
import shutil
import tempfile
from functools import partial
from pathlib import Path

import pytest

from diagnosis_runs import simulate_run, sinusoid_reference
from feeddrive import cli
from feeddrive.data import write_run
from feeddrive.experiments.constant_speed import PAPER_LOADS, constant_speed_runs, stribeck_runs
from feeddrive.experiments.force_open_loop import force_open_loop_runs
from feeddrive.experiments.prbs import prbs_runs
from feeddrive.experiments.prerolling_excitation import prerolling_runs
from feeddrive.experiments.variable_speed import variable_speed_runs
from feeddrive.harness.sensors import Sensors
from feeddrive.model_file import paper_model, save_model

REPO = Path(__file__).resolve().parents[1]
SHOTS = REPO / "build" / "screenshots"
VIEWPORT = (1280, 900)

#: the flags of a quiet headless Chromium on a closed network (no background requests)
FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-dev-shm-usage",
)


def _find(*names: str) -> str | None:
    for n in names:
        if shutil.which(n):
            return shutil.which(n)
    return None


CHROMIUM = _find("chromium", "chromium-browser")
DRIVER = _find("chromedriver")


@pytest.fixture(scope="module")
def browser():
    """One headless Chromium (through chromedriver) for the module, with a fresh profile."""
    if CHROMIUM is None or DRIVER is None:
        pytest.skip(
            "Chromium not installed: needs Debian's chromium and chromium-driver "
            "(`make browser` installs them as root with apt-get)"
        )
    webdriver = pytest.importorskip(
        "selenium.webdriver", reason="selenium not installed (pip install 'feeddrive[test]')"
    )
    from selenium.webdriver.chrome.service import Service

    profile = tempfile.mkdtemp(prefix="feeddrive-chromium-")
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for f in (*FLAGS, f"--user-data-dir={profile}", f"--window-size={VIEWPORT[0]},{VIEWPORT[1]}"):
        opts.add_argument(f)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(executable_path=DRIVER), options=opts)
    driver.execute_cdp_cmd(
        "Emulation.setDeviceMetricsOverride",
        {"width": VIEWPORT[0], "height": VIEWPORT[1], "deviceScaleFactor": 1, "mobile": False},
    )
    yield driver
    driver.quit()
    shutil.rmtree(profile, ignore_errors=True)


def check_page(driver, page: Path, shot: str, shots: Path = SHOTS) -> list[str]:
    """Open ``page``; the problems found (console errors, images not loaded, wider than the
    viewport), after saving a full-page screenshot as ``<shots>/<shot>.png``."""
    driver.get_log("browser")  # drop what an earlier page left
    driver.get(page.resolve().as_uri())
    problems = [
        f"console {e['level']}: {e['message']}"
        for e in driver.get_log("browser")
        if e["level"] == "SEVERE"
    ]
    broken = driver.execute_script(
        "return Array.from(document.images).filter(i => !(i.complete && i.naturalWidth > 0))"
        ".map(i => i.getAttribute('src'))"
    )
    problems += [f"image not loaded: {src}" for src in broken]
    width = driver.execute_script(
        "return Math.max(document.documentElement.scrollWidth, document.body.scrollWidth)"
    )
    if width > VIEWPORT[0]:
        wide = driver.execute_script(
            "return Array.from(document.body.querySelectorAll('*')).filter(e => "
            f"e.getBoundingClientRect().right > {VIEWPORT[0]} || e.scrollWidth > e.clientWidth)"
            ".slice(0, 3)"
            ".map(e => e.tagName + ' ' + Math.round(e.getBoundingClientRect().width) + ' px')"
        )
        problems.append(f"page {width} px wide > {VIEWPORT[0]} px: {wide}")
    shots.mkdir(parents=True, exist_ok=True)
    png = driver.execute_cdp_cmd(
        "Page.captureScreenshot", {"format": "png", "captureBeyondViewport": True}
    )
    (shots / f"{shot}.png").write_bytes(base64.b64decode(png["data"]))
    return problems


# ---------------------------------------------------------------- the checker itself


def test_the_checks_find_a_broken_page(browser, tmp_path):
    """A missing image, a script error and a 2000 px table are each reported."""
    bad = tmp_path / "bad.html"
    bad.write_text(
        "<!DOCTYPE html><html><body><img src='missing.png'>"
        "<script>undefined_function()</script>"
        "<table><tr><td style='min-width:2000px'>wide</td></tr></table></body></html>"
    )
    problems = check_page(browser, bad, "bad", tmp_path)
    assert any("image not loaded: missing.png" in p for p in problems), problems
    assert any("undefined_function" in p for p in problems), problems
    assert any(p.startswith("page ") and "> 1280 px" in p for p in problems), problems
    good = tmp_path / "good.html"
    good.write_text("<!DOCTYPE html><html><body><p>fine</p></body></html>")
    assert check_page(browser, good, "good", tmp_path) == []
    assert (tmp_path / "bad.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ---------------------------------------------------------------- the pages


def _ok(argv: list[str], capsys) -> None:
    rc = cli.main(argv)
    cap = capsys.readouterr()
    assert rc == 0, (argv[0], cap.err[-600:])


def _assert_page(browser, page: Path, shot: str, min_images: int) -> None:
    assert page.is_file(), page
    problems = check_page(browser, page, shot)
    assert not problems, f"{page}:\n" + "\n".join(problems)
    n = browser.execute_script("return document.images.length")
    assert n >= min_images, (page, n)


def test_circle_page(browser, tmp_path, capsys, fmu_path):
    out = tmp_path / "circle"
    _ok(
        [
            "circle",
            "--radius-mm",
            "5",
            "--feed-m-min",
            "2",
            "--feedforward",
            "none",
            "gms",
            "--out",
            str(out),
        ],
        capsys,
    )
    _assert_page(browser, out / "index.html", "circle", 2)


#: a tiny sweep (four runs of 0.2 s) on a model file beside the study
STUDY = {
    "schema": "feeddrive.study/1",
    "name": "browser",
    "model": "base_model.json",
    "experiment": {
        "reference": {
            "type": "sinusoid",
            "amplitude": 0.005,
            "period": 0.2,
            "centre": 0.15,
            "duration": 0.2,
        },
        "controller": {"type": "pid"},
        "skip_start": 0.0,
        "half_width": 0.05,
    },
    "parameters": {"m": {"relative": 0.1}, "friction.F_c": {"relative": 0.1}},
    "design": {"type": "grid", "levels": 2},
    "metrics": ["rms_error", "max_error"],
}


def test_study_page(browser, tmp_path, capsys, fmu_path):
    save_model(paper_model(), tmp_path / "base_model.json")
    (tmp_path / "study.json").write_text(json.dumps(STUDY))
    _ok(["sweep", str(tmp_path / "study.json"), "--out", str(tmp_path / "s"), "--serial"], capsys)
    pages = sorted((tmp_path / "s").glob("*.html"))
    assert pages, list((tmp_path / "s").iterdir())
    for page in pages:
        _assert_page(browser, page, f"study_{page.stem}", 1)


def test_diagnosis_page(browser, tmp_path, capsys, fmu_path):
    run = simulate_run(
        paper_model(), sinusoid_reference(1.5, period=1.5), current_noise=0.005, seed=3, name="d"
    )
    write_run(run, tmp_path / "d.csv")
    model = paper_model()
    model.effects["prerolling"] = False  # a model that lacks something
    save_model(model, tmp_path / "m.json")
    _ok(
        [
            "diagnose",
            str(tmp_path / "d.csv"),
            "--model",
            str(tmp_path / "m.json"),
            "--out",
            str(tmp_path / "diag"),
            "--max-steps",
            "1",
        ],
        capsys,
    )
    _assert_page(browser, tmp_path / "diag" / "report.html", "diagnosis", 1)


def _identification_runs(folder: Path) -> None:
    """Short identification runs: PRBS, two loaded passes over the whole stroke (the maps
    need it), a few Stribeck speeds, open-loop force, variable speed, pre-rolling."""
    params = paper_model().fmu_parameters()
    jobs = (
        partial(prbs_runs, periods=1),
        partial(
            constant_speed_runs, speeds=(40e-3,), loads=PAPER_LOADS[:2], segment=(0.001, 0.299)
        ),
        partial(stribeck_runs, speeds=(2e-3, 20e-3), cruise_time=1.0, min_length=3e-3),
        partial(force_open_loop_runs, n_periods=5),
        partial(variable_speed_runs, duration=2.0),
        partial(prerolling_runs, period=2.0, n_periods=2.0),
    )
    folder.mkdir()
    for k, job in enumerate(jobs):
        for r in job(params, Sensors(seed=k)):
            write_run(r, folder / f"{r.meta['name']}.csv")


@pytest.mark.slow
def test_identification_page(browser, tmp_path, capsys, fmu_path):
    """The identification report (20-30 s: the runs and the identification)."""
    _identification_runs(tmp_path / "runs")
    rc = cli.main(["report", str(tmp_path / "runs"), "--out", str(tmp_path / "id")])
    out = capsys.readouterr().out
    assert rc == 0 and f"model file: {tmp_path / 'id' / 'model.json'}" in out, out[-800:]
    _assert_page(browser, tmp_path / "id" / "index.html", "identification", 5)


def test_run_page(browser, tmp_path, capsys, fmu_path):
    """The main job's report (the paper's reproductions: about 10 s)."""
    _ok(["run", "--out", str(tmp_path / "report")], capsys)
    _assert_page(browser, tmp_path / "report" / "index.html", "run", 4)
