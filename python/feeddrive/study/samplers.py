"""The runs of a study: parameter values per run from its design.

- ``grid``: the full factorial of ``levels`` points over each range (or the given values);
- ``lhs``: scipy.stats.qmc.LatinHypercube (seeded), mapped through each parameter's
  distribution (``ppf``; a range is uniform);
- ``monte_carlo``: independent draws of each parameter's scipy.stats distribution (seeded);
- ``oat``: one at a time: the base point (the model's values), then each parameter at its
  low and its high end with the others at base.

Integer parameters (``friction.N``) are rounded to the nearest integer.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy.stats import qmc

from ..model_file import INTEGER_PARAMETERS
from .spec import ParameterSpec, Study


@dataclass(frozen=True)
class Case:
    """One run of a study: its id, a label (``oat``: which end of which parameter) and values."""

    run: int
    label: str
    values: dict[str, float | int]


def _typed(name: str, v: float) -> float | int:
    return int(round(v)) if name in INTEGER_PARAMETERS else float(v)


def _range(p: ParameterSpec) -> tuple[float, float]:
    """(low, high) of a parameter given by its range (the schema checked both are there)."""
    if p.low is None or p.high is None:
        raise ValueError(f"{p.name}: no range low..high")
    return p.low, p.high


def _grid(params: tuple[ParameterSpec, ...], levels: int) -> np.ndarray:
    axes = [
        np.asarray(p.values) if p.values is not None else np.linspace(*_range(p), levels)
        for p in params
    ]
    return np.array(list(itertools.product(*axes)), dtype=float)


def _lhs(params: tuple[ParameterSpec, ...], runs: int, seed: int) -> np.ndarray:
    u = qmc.LatinHypercube(d=len(params), seed=np.random.default_rng(seed)).random(runs)
    return np.column_stack([p.frozen_distribution().ppf(u[:, j]) for j, p in enumerate(params)])


def _monte_carlo(params: tuple[ParameterSpec, ...], runs: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.column_stack(
        [p.frozen_distribution().rvs(size=runs, random_state=rng) for p in params]
    )


def cases(study: Study) -> list[Case]:
    """Every run of ``study`` in order (run ids 0..n-1), the same on every call."""
    params = study.parameters
    names = study.parameter_names
    d = study.design
    if d["type"] == "oat":
        base = {p.name: _typed(p.name, p.base) for p in params}
        out = [Case(0, "base", dict(base))]
        for p in params:
            for end, v in zip(("low", "high"), _range(p), strict=True):
                values = dict(base)
                values[p.name] = _typed(p.name, float(v))
                out.append(Case(len(out), f"{p.name}={end}", values))
        return out
    if d["type"] == "grid":
        x = _grid(params, d["levels"])
    elif d["type"] == "lhs":
        x = _lhs(params, d["runs"], d["seed"])
    else:
        x = _monte_carlo(params, d["runs"], d["seed"])
    return [
        Case(k, "", {n: _typed(n, v) for n, v in zip(names, row, strict=True)})
        for k, row in enumerate(x)
    ]
