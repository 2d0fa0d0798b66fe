"""identify's run classification: the sidecar's kind, else a signal test that a constant
signal fails; a file name naming a kind must agree with the signals; the reason is kept."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from feeddrive.data import Run
from feeddrive.identify.pipeline import classify_why, group_runs


def _run(x, u, name="stray", i=None, x_ref=None, meta=None) -> Run:
    n = len(x)
    return Run(
        time=np.arange(n) * 5e-4,
        u=u,
        x=x,
        i=i,
        x_ref=x_ref,
        meta=meta or {},
        path=Path(f"/data/{name}.csv"),
    )


N = 2000
RNG = np.random.default_rng(0)
HELD_X = 0.15 + 2e-5 * np.sin(np.arange(N) / 50.0)
PRBS_U = 0.3 + 0.05 * np.sign(np.sin(np.arange(N) / 7.0))


def test_constant_signals_are_not_classified():
    with pytest.raises(ValueError, match=r"stray\.csv: cannot tell.*x constant"):
        classify_why(_run(np.full(N, 0.15), PRBS_U, i=PRBS_U * 0.06))
    with pytest.raises(ValueError, match=r"prbs\.csv: cannot tell.*x constant"):
        classify_why(_run(np.full(N, 0.15), np.zeros(N), name="prbs"))  # the name alone
    with pytest.raises(ValueError, match="u is constant"):
        classify_why(_run(np.linspace(0.1, 0.2, N), np.full(N, 0.2)))


def test_kinds_and_reasons():
    kind, why = classify_why(_run(HELD_X, PRBS_U, i=0.06 * PRBS_U))
    assert kind == "prbs" and "mean crossings" in why
    kind, why = classify_why(_run(np.full(N, 0.15), np.zeros(N), meta={"kind": "prbs"}))
    assert (kind, why) == ("prbs", "the sidecar's kind")
    x = np.linspace(0.10, 0.20, N)
    kind, why = classify_why(_run(x, 0.1 + 0.01 * RNG.standard_normal(N), x_ref=x, name="cv_p1"))
    assert kind == "constant_speed" and why.startswith("file name and signals")
    with pytest.raises(ValueError, match="file name says prbs but the signals say"):
        classify_why(_run(x, 0.1 + 0.01 * RNG.standard_normal(N), x_ref=x, name="prbs_2"))
    # a kind the tools do not know is information only: the signals decide and the reason
    # says the word was not used
    kind, why = classify_why(_run(x, PRBS_U, meta={"kind": "banana"}))
    assert kind == classify_why(_run(x, PRBS_U))[0] and "'banana' is not one of" in why


def test_group_runs_says_where_each_run_went():
    why: list[str] = []
    groups = group_runs(
        [
            _run(HELD_X, PRBS_U, name="a"),
            _run(np.full(N, 0.15), np.zeros(N), name="b", meta={"kind": "prerolling"}),
        ],
        why,
    )
    assert [r.name for r in groups["prbs"]] == ["a"] and [r.name for r in groups["prerolling"]] == [
        "b"
    ]
    assert (
        why[0].startswith("  a: prbs (signals: x held within")
        and "b: prerolling (the sidecar" in why[1]
    )
