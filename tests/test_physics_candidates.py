"""The diagnosis never accepts a model the FMU refuses: a candidate whose identified model
breaks a rule of fmu_src/models/plant/params.c is scored as not significant (unchecked, it would write
friction.sigma2 = -7135 into a model file)."""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.data import Run
from feeddrive.diagnose.context import Context
from feeddrive.diagnose.scoring import score
from feeddrive.effects.viscous import candidate as viscous
from feeddrive.model_file import load_model, paper_model
from feeddrive.physics import compile
from feeddrive.report.diagnosis import write_diagnosis
from feeddrive.residual import residuals
from session_cache import diagnose

PAPER = paper_model()
DSIGMA = -7189.0  #: the data's viscous coefficient is the model's 54 N s/m plus this


def synthetic_runs() -> list[Run]:
    """Two sinusoids whose current follows Eq. 1 of the paper's model (steady friction) with
    sigma2 lowered by 7189 N s/m: a "truth" no FMU can hold."""
    P = compile(PAPER)
    runs = []
    for k, (amp, f) in enumerate(((0.01, 1.3), (0.004, 3.1))):
        t = np.arange(8000) * P.Ts
        w = 2 * np.pi * f
        x = 0.15 + amp * np.sin(w * t)
        v = amp * w * np.cos(w * t)
        a = -amp * w**2 * np.sin(w * t)
        F = P.m * a + P.F_cg(x) + P.friction.steady(v) + DSIGMA * v
        i = F / P.K_f(x)
        # i[k] holds over [t_k, t_k+1): the residual sees (i[k-1] + i[k]) / 2 at t_k
        runs.append(Run(time=t, u=i / P.current.G1, x=x, i=i, meta={"name": f"sin{k}"}))
    return runs


def test_refused_candidate_is_not_significant_and_names_the_rule():
    res = residuals(synthetic_runs(), PAPER.with_effect("prerolling", False))
    ctx = Context(res, PAPER.with_effect("prerolling", False))
    s = score(ctx, viscous(ctx)[0])
    assert s.theta[0] == pytest.approx(DSIGMA, rel=0.02)  # the fit itself is right
    assert s.improvement > 0.5  # and explains the residual
    assert s.refused is not None and s.refused.startswith("friction.sigma2 = -71")
    assert s.refused.endswith("is out of range: allowed [0, inf) N.s/m")
    assert not s.significant


def test_diagnosis_writes_only_models_the_fmu_accepts(tmp_path):
    start = PAPER.with_effect("prerolling", False)
    diag = diagnose(synthetic_runs(), start, max_steps=2, closed_loop=False)
    write_diagnosis(diag, tmp_path)
    assert all(s.effect != "viscous" for s in diag.steps)
    compile(diag.model)  # raises if the FMU would refuse it
    assert diag.model.parameters["friction.sigma2"] >= 0.0
    for path in tmp_path.glob("model*.json"):
        compile(load_model(path))  # every model file written loads
