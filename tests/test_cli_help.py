"""The command line answers at once and speaks one vocabulary: ``--version``; ``--help``
imports no stage (no numpy, scipy, fmpy, matplotlib, dask, nor the package's stages); every
command's help says what it reads and writes and shows an example that parses; every
argument has a help text; ``--out``, ``--model``, ``--force``, ``--workers`` mean the same in
every command; the choices the parser offers are those of the modules that define them."""

from __future__ import annotations

import argparse
import json
import shlex
import subprocess
import sys

import pytest

from feeddrive import __version__, cli

PARSER = cli.build_parser()
SUB = next(a for a in PARSER._actions if isinstance(a, argparse._SubParsersAction))
ROLES = cli.path_roles(PARSER)

#: what --help may import of the package: the package itself, the parser and its one helper
LIGHT = {
    "feeddrive",
    "feeddrive.cli",
    "feeddrive.cli.arguments",
    "feeddrive.cli.data_commands",
    "feeddrive.cli.simulation_commands",
    "feeddrive.inputs",
}
HEAVY = ("numpy", "scipy", "fmpy", "matplotlib", "dask", "distributed", "pandas", "pyarrow", "tqdm")


def test_version(capsys):
    with pytest.raises(SystemExit) as e:
        cli.main(["--version"])
    assert e.value.code == 0
    assert (
        capsys.readouterr().out.strip()
        == f"feeddrive {__version__}"
        == f"feeddrive {cli.version()}"
    )


def test_help_imports_no_stage():
    """``--help`` of the top level and of every command, in a fresh interpreter: the modules
    loaded afterwards (sys.modules), not a time."""
    code = (
        "import json, sys\nfrom feeddrive.cli import main\nout = {}\n"
        f"for cmd in {['', *SUB.choices]!r}:\n"
        "    try:\n        main([cmd, '--help'] if cmd else ['--help'])\n"
        "    except SystemExit:\n        pass\n"
        "    out[cmd] = sorted(m for m in sys.modules if m.split('.')[0] in "
        f"{HEAVY!r} or m.startswith('feeddrive'))\n"
        "print(json.dumps(out), file=sys.stderr)\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr[-2000:]
    loaded = json.loads(p.stderr.strip().splitlines()[-1])
    assert set(loaded) == {"", *SUB.choices}
    for cmd, mods in loaded.items():
        heavy = [m for m in mods if m.split(".")[0] in HEAVY]
        stages = [m for m in mods if m.startswith("feeddrive") and m not in LIGHT]
        assert not heavy and not stages, (cmd or "top level", heavy[:5], stages[:5])


def test_every_command_has_its_module():
    """Each command's work is a module of feeddrive.commands with ``main``."""
    import importlib

    for name in SUB.choices:
        assert callable(importlib.import_module(f"feeddrive.commands.{name}").main), name


def test_a_command_still_imports_its_stages_when_it_runs(tmp_path):
    """The lazy imports are real: `model` (a cheap command) runs and writes its file."""
    p = subprocess.run(
        [
            sys.executable,
            "-m",
            "feeddrive.cli",
            "model",
            "--paper",
            "--out",
            str(tmp_path / "m.json"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert p.returncode == 0, p.stderr
    assert json.loads((tmp_path / "m.json").read_text())["parameters"]["friction.F_s"] == 26.1


def _examples(text: str) -> list[list[str]]:
    """The ``feeddrive ...`` command lines of a help text's example section."""
    body = text.split("\nexample:\n", 1)[1]
    lines = [ln.strip() for ln in body.replace("\\\n", " ").splitlines()]
    return [shlex.split(ln)[1:] for ln in lines if ln.startswith("feeddrive ")]


@pytest.mark.parametrize("name", sorted(SUB.choices))
def test_every_command_says_what_it_reads_writes_and_shows_an_example(name):
    p = SUB.choices[name]
    text = p.format_help()
    for section in ("\nreads:\n  ", "\nwrites:\n  ", "\nexample:\n  "):
        assert section in text, (name, section)
    assert "[" not in p.description[:1] and p.description.endswith("."), p.description
    examples = _examples(text)
    assert examples and any(ex[0] == name for ex in examples), (name, examples)
    for argv in examples:  # every example is a valid command line
        a = PARSER.parse_args(argv)
        assert a.command == argv[0]


@pytest.mark.parametrize("name", sorted(SUB.choices))
def test_every_argument_has_help(name):
    missing = [a.dest for a in SUB.choices[name]._actions if not a.help]
    assert not missing, (name, missing)


def _option(name: str, flag: str) -> argparse.Action | None:
    return next((a for a in SUB.choices[name]._actions if flag in a.option_strings), None)


def test_one_option_vocabulary():
    writers = {n for n, r in ROLES.items() if set(r.values()) & set(cli.OUTPUT_ROLES)}
    assert writers == set(SUB.choices) - {"validate"}
    for name in SUB.choices:
        out, model, force, workers = (
            _option(name, f) for f in ("--out", "--model", "--force", "--workers")
        )
        if name in writers:  # every command that writes: --out for it, and --force
            assert out is not None and ROLES[name][out.dest] in cli.OUTPUT_ROLES, name
            assert force is not None and force.nargs == 0 and force.default is False, name
            assert "replace" in force.help, (name, force.help)
        if model is not None:  # --model is a model file the command reads
            assert ROLES[name][model.dest] == cli.FILE, name
        if workers is not None:  # --workers: processes, an integer >= 1
            assert workers.type is cli.STEPS, name


def test_choices_are_the_modules_own():
    from feeddrive.commands.system import systems
    from feeddrive.experiments.campaign import FORMATS, MAX_REPEATS
    from feeddrive.xy.circle_test import FEEDFORWARD
    from feeddrive.xy.machine import MISMATCH

    assert cli.MAX_REPEATS == MAX_REPEATS
    assert tuple(cli.RUN_FORMATS) == tuple(FORMATS)
    from feeddrive.study.bootstrap import METHODS

    assert tuple(cli.INTERVAL_METHODS) == tuple(METHODS)
    assert set(cli.FEEDFORWARD_CHOICES) == set(FEEDFORWARD)
    assert tuple(cli.MISMATCH_CHOICES) == tuple(MISMATCH)
    assert tuple(cli.SYSTEM_CASES) == tuple(systems())


def test_top_level_help_names_every_command_and_the_vocabulary(capsys):
    with pytest.raises(SystemExit):
        cli.main(["--help"])
    text = capsys.readouterr().out
    for name in SUB.choices:
        assert f"\n    {name}" in text, name
    for flag in ("--out", "--model", "--force", "--workers"):
        assert f"\n  {flag} " in text, flag
