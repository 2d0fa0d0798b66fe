"""The command line and the files it touches: no command writes over a file it reads (every
command and output option of the parser against each of its inputs), special files (FIFOs,
devices, symbolic link loops) refused, a bounded header read, one-line messages whatever the
file name, and numbers in a run CSV as plain ASCII decimal/exponent only."""

from __future__ import annotations

import json
import os
import re
import shutil
import stat
import threading
from pathlib import Path

import numpy as np
import pytest

from diagnosis_runs import simulate_run, sinusoid_reference
from feeddrive import cli, data_csv
from feeddrive.data import DataError, load_run, write_run
from feeddrive.harness.controller_fmu import CONTROLLER_FMU_ENV, controller_fmu_path
from feeddrive.model_description import FMU_ENV
from feeddrive.model_file import load_model, paper_model, save_model
from feeddrive.outputs import output_dir
from feeddrive.realdata import odrive

PAPER = paper_model()
ROLES = cli.path_roles(cli.build_parser())

#: arguments of the sub-commands that are not paths (every other argument has a role)
NOT_PATHS = {
    "paper",
    "emps",
    "force",
    "case",
    "run",
    "radius_mm",
    "feed_m_min",
    "direction",
    "feedforward",
    "mismatch",
    "osp",
    "seed",
    "repeats",
    "bootstrap",
    "interval_method",
    "level",
    "workers",
    "scheduler",
    "serial",
    "no_progress",
    "position_friction",
    "max_steps",
    "force_gain",
    "window",
    "blocks",
    "no_closed_loop",
    "resume",
    "fmi",
    "format",
    "help",
    "stroke",
    "v_max",
    "a_max",
    "u_limit",
    "loads",
    "html",
}

#: a tiny sweep (two runs of 0.2 s) on a model file beside the study
STUDY = {
    "schema": "feeddrive.study/1",
    "name": "guard",
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
    "parameters": {"m": {"relative": 0.1}},
    "design": {"type": "grid", "levels": 2},
    "metrics": ["rms_error"],
}

RULE = re.compile(r"an input of this command|a folder this command reads")


def test_every_argument_of_every_command_has_a_role_or_is_no_path():
    parser = cli.build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    assert set(sub.choices) == set(ROLES)
    for name, p in sub.choices.items():
        dests = {a.dest for a in p._actions}
        untagged = dests - set(ROLES[name]) - NOT_PATHS
        assert not untagged, (name, untagged)
        outs = [a.dest for a in p._actions if any("out" in s for s in a.option_strings)]
        assert all(ROLES[name][d] in cli.OUTPUT_ROLES for d in outs), (name, outs)


@pytest.fixture(scope="module")
def run_text(fmu_path):
    run = simulate_run(
        PAPER, sinusoid_reference(0.5, period=0.5), current_noise=0.005, seed=5, name="a"
    )
    return run


def _inputs(root: Path, role: str, run) -> tuple[str, list[Path]]:
    """Make the input of ``role`` under ``root``: (the argument's value, the paths it reads)."""
    root.mkdir(parents=True, exist_ok=True)
    if role == cli.RUN:
        write_run(run, root / "a.csv")
        return str(root / "a.csv"), [root / "a.csv", root / "a.json"]
    if role == cli.RUNS:
        write_run(run, root / "a.csv")
        return str(root), [root / "a.csv", root / "a.json"]
    if role == cli.FILE:
        save_model(PAPER, root / "m.json")
        return str(root / "m.json"), [root / "m.json"]
    if role == cli.TREE:
        (root / "realdata" / "odrive-cogging").mkdir(parents=True)
        (root / "realdata" / "odrive-cogging" / "notes.md").write_text("measured\n")
        return str(root), [root / "realdata" / "odrive-cogging" / "notes.md", root]
    if role == cli.STUDY:
        save_model(PAPER, root / "base_model.json")
        (root / "friction_study.json").write_text(json.dumps(STUDY))
        return str(root / "friction_study.json"), [
            root / "friction_study.json",
            root / "base_model.json",
        ]
    raise AssertionError(role)


def _cases() -> list[tuple[str, str, str, int]]:
    """(command, output argument, input argument, index of the read path) for every pair."""
    cases = []
    for name, roles in ROLES.items():
        for out, orole in roles.items():
            if orole not in cli.OUTPUT_ROLES:
                continue
            for dest, role in [*roles.items(), ("fmu", cli.FILE), ("controller_fmu", cli.FILE)]:
                if role in cli.OUTPUT_ROLES:
                    continue
                n = {cli.RUN: 2, cli.RUNS: 2, cli.FILE: 1, cli.TREE: 2, cli.STUDY: 2}[role]
                n += orole == cli.OUT_DIR  # the folder that holds the first input
                cases += [(name, out, dest, k) for k in range(n)]
    return cases


CASES = _cases()


def _state(root: Path) -> dict[str, tuple[int, bytes]]:
    return {
        str(p.relative_to(root)): (p.lstat().st_mode, p.read_bytes() if p.is_file() else b"")
        for p in sorted(root.rglob("*"))
    }


def _flag(action) -> str:
    return action.option_strings[-1] if action.option_strings else ""


def _argv(name: str, values: dict[str, str]) -> list[str]:
    """The command line of ``name`` with ``values`` for its path arguments (and --force)."""
    p = next(a for a in cli.build_parser()._actions if a.dest == "command").choices[name]
    argv = [name]
    for a in p._actions:
        if a.dest in values:
            argv += [values[a.dest]] if not a.option_strings else [_flag(a), values[a.dest]]
        elif a.dest == "force":
            argv.append("--force")
    if name == "model":
        argv.append("--paper")
    return argv


def test_every_command_has_outputs_covered():
    covered = {c for c, *_ in CASES}
    writers = {n for n, r in ROLES.items() if set(r.values()) & set(cli.OUTPUT_ROLES)}
    assert covered == writers and {"identify", "diagnose", "report", "sweep", "model"} <= writers


@pytest.mark.parametrize("name,out,dest,k", CASES, ids=[f"{c}-{o}-{d}-{k}" for c, o, d, k in CASES])
def test_no_command_writes_over_its_inputs(
    tmp_path, capsys, monkeypatch, run_text, fmu_path, name, out, dest, k
):
    root = tmp_path / "in"
    values: dict[str, str] = {}
    reads: dict[str, list[Path]] = {}
    for d, role in ROLES[name].items():
        if role not in cli.OUTPUT_ROLES:
            values[d], reads[d] = _inputs(root / d, role, run_text)
    for d, src, env in (
        ("fmu", fmu_path, FMU_ENV),
        ("controller_fmu", controller_fmu_path(), CONTROLLER_FMU_ENV),
    ):
        (root / d).mkdir(parents=True)
        reads[d] = [Path(shutil.copy(src, root / d / Path(src).name))]
        monkeypatch.setenv(env, str(reads[d][0]))
    paths = reads[dest] + [reads[dest][0].parent]
    for d, role in ROLES[name].items():
        if role in cli.OUTPUT_ROLES:
            values[d] = str(tmp_path / "elsewhere" / d)
    values[out] = str(paths[k])
    for p in root.rglob("*"):
        if p.is_file():
            p.chmod(0o644)
    before = _state(root)
    capsys.readouterr()
    rc = cli.main(_argv(name, values))
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert rc == 2, (rc, cap.out[-300:], cap.err[-300:])
    assert len(err) == 1 and err[0].startswith(f"feeddrive {name}: "), err
    assert RULE.search(err[0]) and str(paths[k]) in err[0], err[0]
    assert _state(root) == before
    assert not (tmp_path / "elsewhere").exists()


def test_identify_out_over_a_sidecar_path_of_a_run_without_one(tmp_path, capsys, run_text):
    """A run without a sidecar: its sidecar path would become one (the model as its metadata)."""
    runs = tmp_path / "runs"
    runs.mkdir()
    write_run(run_text, runs / "a.csv")
    (runs / "a.json").unlink()
    assert cli.main(["identify", str(runs), "--out", str(runs / "a.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "sidecar" in err[0] and RULE.search(err[0])
    assert sorted(p.name for p in runs.iterdir()) == ["a.csv"]


def test_identify_out_a_link_to_an_input(tmp_path, capsys, run_text):
    runs = tmp_path / "runs"
    runs.mkdir()
    write_run(run_text, runs / "a.csv")
    before = (runs / "a.json").read_bytes()
    os.link(runs / "a.json", tmp_path / "other.json")
    (tmp_path / "link.json").symlink_to(runs / "a.json")
    (tmp_path / "dangling.json").symlink_to(runs / "b.json")  # sidecar path of b.csv
    (runs / "b.csv").write_bytes((runs / "a.csv").read_bytes())
    for out in ("other.json", "link.json", "dangling.json"):
        assert cli.main(["identify", str(runs), "--out", str(tmp_path / out)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and RULE.search(err[0]), (out, err)
    assert (runs / "a.json").read_bytes() == before and not (runs / "b.json").exists()


# ---------------------------------------------------------------- special files


def _one_line(capsys, name: str) -> str:
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"feeddrive {name}: "), cap.err[-500:]
    assert "Traceback" not in cap.err
    return err[0]


@pytest.mark.parametrize("name", [n for n, r in ROLES.items() if "out" in r])
def test_out_a_symbolic_link_loop(tmp_path, capsys, name):
    loop = tmp_path / "loop"
    loop.symlink_to(loop)
    values = {d: str(loop) if d == "out" else str(tmp_path / "none" / d) for d in ROLES[name]}
    assert cli.main(_argv(name, values)) == 2
    msg = _one_line(capsys, name)
    assert "symbolic link loop" in msg and str(loop) in msg
    assert loop.is_symlink() and os.readlink(loop) == str(loop)


@pytest.fixture
def unblock():
    """Opens the FIFOs given to it for writing after a while and closes them: a reader that
    blocked on one then sees an empty file instead of hanging the suite."""
    fifos: list[Path] = []
    stop = threading.Event()

    def opener():
        wait = 20.0
        while not stop.wait(wait):
            wait = 1.0
            for f in fifos:
                try:
                    os.close(os.open(f, os.O_WRONLY | os.O_NONBLOCK))
                except OSError:
                    pass

    t = threading.Thread(target=opener, daemon=True)
    t.start()
    yield fifos
    stop.set()
    t.join()


def _fifo(path: Path, fifos: list[Path]) -> Path:
    os.mkfifo(path)
    fifos.append(path)
    return path


def test_fifo_run_sidecar_and_model_refused(tmp_path, capsys, unblock, run_text):
    save_model(PAPER, tmp_path / "m.json")
    fifo = _fifo(tmp_path / "f.csv", unblock)
    assert cli.main(["validate", str(fifo), "--model", str(tmp_path / "m.json")]) == 2
    msg = _one_line(capsys, "validate")
    assert str(fifo) in msg and "FIFO" in msg and "regular file" in msg
    runs = tmp_path / "runs"
    runs.mkdir()
    write_run(run_text, runs / "a.csv")
    _fifo(runs / "b.csv", unblock)
    assert cli.main(["identify", str(runs), "--out", str(tmp_path / "id.json")]) == 2
    assert "FIFO" in _one_line(capsys, "identify")
    (runs / "b.csv").unlink()
    (runs / "a.json").unlink()
    _fifo(runs / "a.json", unblock)
    assert (
        cli.main(
            [
                "diagnose",
                str(runs / "a.csv"),
                "--model",
                str(tmp_path / "m.json"),
                "--out",
                str(tmp_path / "d"),
            ]
        )
        == 2
    )
    msg = _one_line(capsys, "diagnose")
    assert "FIFO" in msg and str(runs / "a.json") in msg
    fm = _fifo(tmp_path / "fm.json", unblock)
    assert cli.main(["validate", str(runs / "a.csv"), "--model", str(fm)]) == 2
    assert "FIFO" in _one_line(capsys, "validate")
    fs = _fifo(tmp_path / "s.json", unblock)
    assert cli.main(["sweep", str(fs), "--out", str(tmp_path / "s")]) == 2
    assert "FIFO" in _one_line(capsys, "sweep")
    assert not (tmp_path / "id.json").exists() and not (tmp_path / "d").exists()


@pytest.mark.parametrize("device", ["/dev/null", "/dev/zero"])
def test_device_as_a_run_refused(tmp_path, capsys, device):
    if not Path(device).exists():
        pytest.skip(f"no {device}")
    (tmp_path / "runs").mkdir()
    (tmp_path / "runs" / "dev.csv").symlink_to(device)
    assert cli.main(["validate", device]) == 2
    msg = _one_line(capsys, "validate")
    assert device in msg and "character device" in msg
    assert cli.main(["identify", str(tmp_path / "runs"), "--out", str(tmp_path / "m.json")]) == 2
    assert "character device" in _one_line(capsys, "identify")
    with pytest.raises(DataError, match="not a regular file"):
        load_run(tmp_path / "runs" / "dev.csv")


def test_huge_file_without_a_line_end_refused_after_a_bounded_read(tmp_path, capsys):
    """2 GiB of NUL bytes (sparse): the header check reads a few KiB, the message is short."""
    big = tmp_path / "zeros.csv"
    with open(big, "wb") as f:
        f.truncate(2 << 30)
    assert cli.main(["validate", str(big)]) == 2
    msg = _one_line(capsys, "validate")
    assert str(big) in msg and "line 1" in msg and len(msg) < 400
    with pytest.raises(DataError, match="no line end"):
        load_run(big)


def test_long_header_refused_with_a_short_message(tmp_path):
    p = tmp_path / "long.csv"
    p.write_text("time,u,x," + "y" * (1 << 20) + "\n0,0,0,1\n")
    with pytest.raises(DataError) as e:
        load_run(p)
    assert len(str(e.value)) < 400 and e.value.line == 1


@pytest.mark.parametrize(
    "name",
    ["bad\nname.csv", "bad\rname.csv", "esc\x1b[2Jname.csv", "sep\u2028name.csv", "tab\tname.csv"],
)
def test_message_is_one_line_whatever_the_file_name(tmp_path, capsys, name):
    d = tmp_path / ("dir\nwith newline")
    d.mkdir()
    p = d / name
    p.write_text("time,u\n0,1\n")  # no column x
    assert cli.main(["validate", str(p)]) == 2
    msg = _one_line(capsys, "validate")
    assert "required column missing" in msg and "\\n" in msg
    assert not any(c in msg for c in "\r\x1b\u2028\t")
    loop = d / "loop\nname"
    loop.symlink_to(loop)
    assert cli.main(["model", "--paper", "--out", str(loop)]) == 2
    assert "symbolic link loop" in _one_line(capsys, "model")


# ---------------------------------------------------------------- numbers


GOOD_NUMBERS = ["1", "-1.5e-3", "+.5", "5.", "1E+05", "0.000", " 2.5", "3.25 ", "-0", "1e-300"]
BAD_NUMBERS = [
    "0.1_2",
    "1_000",
    "\u0661.\u0665",
    "\u0660",
    "\uff11",
    "\u0967",
    "1\u00a0",
    "0x10",
    "1,5e",
    "\u221e",
]


def _run_csv(cells: list[str], quoted: bool = False) -> str:
    rows = ["time,u,x,note"]
    for k, c in enumerate(cells):
        q = f'"{c}"' if quoted else c
        rows.append(f"{k * 1e-3!r},{q},0.{k + 1},text")
    return "\n".join(rows) + "\n"


@pytest.mark.parametrize("quoted", [False, True])
def test_plain_ascii_numbers_read(tmp_path, quoted):
    p = tmp_path / "ok.csv"
    p.write_text(_run_csv(GOOD_NUMBERS, quoted), encoding="utf-8")
    run = load_run(p)
    assert np.array_equal(run.u, [float(c) for c in GOOD_NUMBERS])


@pytest.mark.parametrize("quoted", [False, True])
@pytest.mark.parametrize("cell", [c for c in BAD_NUMBERS if "," not in c])
def test_number_not_plain_ascii_refused_naming_file_line_column(tmp_path, capsys, cell, quoted):
    p = tmp_path / "bad.csv"
    cells = ["0.5"] * 5
    cells[3] = cell
    p.write_text(_run_csv(cells, quoted), encoding="utf-8")
    with pytest.raises(DataError) as e:
        load_run(p)
    assert e.value.line == 5 and e.value.column == "u" and "plain ASCII decimal" in str(e.value)
    assert cli.main(["validate", str(p)]) == 2
    msg = _one_line(capsys, "validate")
    assert str(p) in msg and "line 5" in msg and "'u'" in msg


def test_extra_column_of_not_plain_numbers_kept_as_text(tmp_path):
    p = tmp_path / "extra.csv"
    p.write_text("time,u,x,code\n0,1,0.1,1_0\n0.001,1,0.2,2\n", encoding="utf-8")
    run = load_run(p)
    assert run.extra["code"].dtype.kind == "U" and list(run.extra["code"]) == ["1_0", "2"]
    p.write_text("time,u,x,code\n0,1,0.1,10\n0.001,1,0.2,2\n", encoding="utf-8")
    assert load_run(p).extra["code"].dtype.kind == "f"


def test_mode_of_a_replaced_output_kept_when_it_is_not_an_input(tmp_path):
    """A model file written again keeps its mode (the atomic replace does not turn 0644 into
    the temporary file's 0600)."""
    out = tmp_path / "m.json"
    save_model(PAPER, out)
    out.chmod(0o644)
    assert cli.main(["model", "--paper", "--out", str(out), "--force"]) == 0
    assert stat.S_IMODE(out.stat().st_mode) == 0o644


@pytest.mark.parametrize("name", sorted(ROLES))
def test_argument_errors_are_one_line(capsys, name):
    """argparse's refusals (an unknown option, a missing argument) are one line, exit 2."""
    for argv in ([name, "--no-such-option", "a\nb"], [name, "--out"]):
        with pytest.raises(SystemExit) as e:
            cli.main(argv)
        assert e.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("feeddrive"), err


def test_json_input_larger_than_the_limit_refused_unread(tmp_path, capsys):
    """A 64 MiB model file (sparse: NUL bytes) is refused after reading 16 MiB + 1 byte."""
    big = tmp_path / "big.json"
    with open(big, "wb") as f:
        f.truncate(64 << 20)
    assert cli.main(["sweep", str(big), "--out", str(tmp_path / "o")]) == 2
    msg = _one_line(capsys, "sweep")
    assert str(big) in msg and "larger than 16 MiB" in msg
    with pytest.raises(ValueError, match="larger than 16 MiB"):
        load_model(big)
    run = tmp_path / "r.csv"
    run.write_text("time,u,x\n0,0,0\n0.001,1,0.1\n")
    side = tmp_path / "r.json"
    os.link(big, side)
    with pytest.raises(DataError, match="larger than 16 MiB"):
        load_run(run)


def test_realdata_arrays_special_and_empty_files_refused(tmp_path, unblock):
    """The shared folder's .npy files (report --shared): a FIFO, a device and an empty file
    are refused with a ValueError naming the file (no block, no EOFError)."""
    fifo = _fifo(tmp_path / "cogging_measure_final_a_16.npy", unblock)
    with pytest.raises(ValueError, match="FIFO"):
        odrive.load_map(fifo)
    (tmp_path / "slow.npy").symlink_to("/dev/zero")
    with pytest.raises(ValueError, match="character device"):
        odrive.load_slow_run(tmp_path / "slow.npy")
    (tmp_path / "empty.npy").write_bytes(b"")
    with pytest.raises(ValueError, match=r"empty\.npy: empty or cut short"):
        odrive.load_slow_run(tmp_path / "empty.npy")


def test_output_folder_mode_kept_or_from_the_umask(tmp_path):
    ref = tmp_path / "ref"
    ref.mkdir()  # what mkdir gives here (umask)
    out = tmp_path / "o"
    with output_dir(out) as d:
        (d / "a.txt").write_text("a")
    assert stat.S_IMODE(out.stat().st_mode) == stat.S_IMODE(ref.stat().st_mode)
    out.chmod(0o750)
    with output_dir(out) as d:
        (d / "a.txt").write_text("b")
    assert stat.S_IMODE(out.stat().st_mode) == 0o750 and (out / "a.txt").read_text() == "b"


@pytest.mark.parametrize("quoted", [False, True])
def test_data_line_without_an_end_refused_after_a_bounded_read(tmp_path, capsys, quoted):
    """A good header, two rows, then 64 MiB without a line end (sparse NUL bytes, or a
    quoted field): refused naming line 4, without reading the line whole."""
    p = tmp_path / "long.csv"
    with open(p, "wb") as f:
        f.write(b"time,u,x\n0,0,0\n0.001,1,0.1\n" + (b'"' if quoted else b"0.002,"))
        f.truncate(64 << 20)
    with pytest.raises(DataError, match="line longer than") as e:
        load_run(p)
    assert e.value.line == 4
    assert cli.main(["validate", str(p)]) == 2
    msg = _one_line(capsys, "validate")
    assert str(p) in msg and "line 4" in msg and len(msg) < 400


@pytest.mark.parametrize("ending", ["\n", "\r\n", "\r"])
def test_line_ends_across_read_blocks(tmp_path, monkeypatch, ending):
    """Blocks cut anywhere (a "\\r\\n" in two too): the same rows as one read, blank lines at
    the end only."""
    rows = [f"{k * 1e-3!r},{k % 7 - 3},{k * 1e-4!r}" for k in range(300)]
    text = ending.join(["time,u,x", *rows]) + ending + ending
    p = tmp_path / "r.csv"
    p.write_bytes(text.encode())
    want = load_run(p)
    for size in (7, 8, 13, 64):
        monkeypatch.setattr(data_csv, "_CHUNK_CHARS", size)
        got = load_run(p)
        assert np.array_equal(got.time, want.time) and np.array_equal(got.u, want.u)
    assert want.n == 300
