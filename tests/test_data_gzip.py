"""Gzip-compressed recordings (``run.csv.gz`` + ``run.json``): written reproducibly, read as a
stream with the same chunks, rules and messages as plain CSV, found in folders beside
``*.csv``; a broken gzip stream is one line naming the file (exit 2 from a command)."""

from __future__ import annotations

import gzip
import json

import numpy as np
import pytest

from feeddrive import data_csv
from feeddrive.cli import main
from feeddrive.data import (
    RECORDING_DECIMALS,
    DataError,
    Run,
    load_run,
    load_runs,
    run_files,
    sidecar_path,
    write_run,
)
from feeddrive.outputs import Reads


def _run(n: int = 3000, seed: int = 0) -> Run:
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 5e-4
    x = 0.1 + 0.02 * np.sin(2 * np.pi * t) + 1e-7 * rng.standard_normal(n)
    u = 2.0 * np.cos(2 * np.pi * t) + 0.01 * rng.standard_normal(n)
    return Run(
        time=t,
        u=u,
        x=x,
        i=0.5 * u,
        x_ref=x + 1e-6,
        F_load=np.full(n, 54.9),
        meta={"name": "r", "kind": "prerolling"},
    )


def test_gzip_run_is_the_plain_run_compressed(tmp_path):
    run = _run()
    write_run(run, tmp_path / "a.csv", RECORDING_DECIMALS)
    write_run(run, tmp_path / "b.csv.gz", RECORDING_DECIMALS)
    gz = (tmp_path / "b.csv.gz").read_bytes()
    assert gz[:2] == b"\x1f\x8b" and gz[4:8] == b"\0\0\0\0"  # gzip, mtime 0
    assert gzip.decompress(gz) == (tmp_path / "a.csv").read_bytes()
    assert len(gz) < 0.5 * (tmp_path / "a.csv").stat().st_size
    write_run(run, tmp_path / "b.csv.gz", RECORDING_DECIMALS)
    assert (tmp_path / "b.csv.gz").read_bytes() == gz  # reproducible bytes
    assert sidecar_path(tmp_path / "b.csv.gz") == tmp_path / "b.json"
    assert json.loads((tmp_path / "b.json").read_text())["kind"] == "prerolling"
    a, b = load_run(tmp_path / "a.csv"), load_run(tmp_path / "b.csv.gz")
    assert b.name == "b" and b.meta == a.meta
    for name, arr in a.columns().items():
        np.testing.assert_array_equal(b.columns()[name], arr, err_msg=name)
    # the values written: each within half a digit of its column's decimals
    for name, d in RECORDING_DECIMALS.items():
        assert np.max(np.abs(b.columns()[name] - run.columns()[name])) <= 0.5 * 10.0**-d * 1.001


def test_folders_list_both_kinds(tmp_path):
    write_run(_run(200), tmp_path / "one.csv.gz")
    write_run(_run(200, 1), tmp_path / "two.csv")
    (tmp_path / "notes.txt").write_text("x")
    assert [p.name for p in run_files(tmp_path)] == ["one.csv.gz", "two.csv"]
    assert [r.name for r in load_runs(tmp_path)] == ["one", "two"]
    reads = {p.name for p, _ in Reads.of(run_folders=[tmp_path]).files}
    assert {"one.csv.gz", "one.json", "two.csv", "two.json"} <= reads
    write_run(_run(200), tmp_path / "two.csv.gz")  # two names of one run: one sidecar
    with pytest.raises(DataError, match=r"two.csv.gz.*two.csv is the same run's name"):
        load_runs(tmp_path)


BROKEN = [  # (text, line, column, words)
    ("time,u,x\n0,0,0\n0.001,abc,1\n", 3, "u", "not a number"),
    ("time,u,x\n0,0,0\n0,1,1\n", 3, "time", "repeats"),
    ("time,u\n0,0\n1,1\n", 1, "x", "required column missing"),
    ("time,u,x\n0,0,0\n1,1\n", 3, "x", "2 fields"),
]


@pytest.mark.parametrize("chunk", [None, 1])
def test_gzip_errors_name_the_line_as_plain_csv(tmp_path, monkeypatch, chunk):
    if chunk is not None:  # every line on a chunk boundary
        monkeypatch.setattr(data_csv, "_CHUNK_CHARS", 8 * chunk)
        monkeypatch.setattr(data_csv, "_CHUNK_ROWS", chunk)
    for k, (text, line, column, words) in enumerate(BROKEN):
        plain, packed = tmp_path / f"{k}.csv", tmp_path / f"{k}z.csv.gz"
        plain.write_text(text)
        packed.write_bytes(gzip.compress(text.encode()))
        with pytest.raises(DataError) as ep:
            load_run(plain)
        with pytest.raises(DataError) as ez:
            load_run(packed)
        assert (
            (ez.value.line, ez.value.column, ez.value.problem)
            == (ep.value.line, ep.value.column, ep.value.problem)
            == (line, column, ep.value.problem)
        )
        assert words in ez.value.problem and str(packed) in str(ez.value)
    run = _run(500)
    write_run(run, tmp_path / "big.csv.gz")  # many chunks: same values
    np.testing.assert_array_equal(load_run(tmp_path / "big.csv.gz").x, run.x)


def _corrupt(tmp_path):
    write_run(_run(), tmp_path / "ok.csv.gz", RECORDING_DECIMALS)
    good = (tmp_path / "ok.csv.gz").read_bytes()
    flipped = bytearray(good)
    flipped[-6] ^= 0xFF  # the CRC
    return {
        "truncated": good[: len(good) // 2],
        "not_gzip": b"time,u,x\n0,0,0\n1,1,1\n",
        "crc": bytes(flipped),
        "empty": b"",
    }


@pytest.mark.parametrize("case", ["truncated", "not_gzip", "crc", "empty"])
def test_corrupt_gzip_is_one_line_naming_the_file(tmp_path, capsys, case):
    data = _corrupt(tmp_path)[case]
    d = tmp_path / "runs"
    d.mkdir()
    bad = d / "run.csv.gz"
    bad.write_bytes(data)
    with pytest.raises(DataError, match="not a valid gzip file") as e:
        load_run(bad)
    assert e.value.path == bad and "\n" not in str(e.value)
    for cmd, argv in {
        "validate": ["validate", str(bad)],
        "identify": ["identify", str(d), "--out", str(tmp_path / "m.json")],
    }.items():
        capsys.readouterr()
        assert main(argv) == 2, cmd
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith(f"feeddrive {cmd}: ") and str(bad) in err[0], err
        assert "not a valid gzip file" in err[0] and "Traceback" not in err[0]
        assert bad.read_bytes() == data and not (tmp_path / "m.json").exists()
