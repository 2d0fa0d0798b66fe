"""The X-Y table of the circular test: two linear-motor axes, each its own parameter set.

Defaults (the Y axis carries the X axis):

- **X**: the paper's drive (``paper_parameters()``, m = 16.1 kg).
- **Y**: m = :data:`Y_MASS` = 40 kg (its own slide, 16.1 kg, plus the X axis it carries:
  slide, magnet track and rails, ~24 kg); the friction of its more heavily loaded guides
  x :data:`Y_FRICTION` = 1.5 (F_s, F_c and the GMS stiffnesses k_i, so the pre-sliding
  travels nu_i F_s / k_i stay; V_s, delta, C, sigma2 and nu_i unchanged); its magnet track
  shifted by :data:`Y_MAGNET_SHIFT` = a quarter pitch (9.375 mm): every periodic cogging and
  ripple harmonic j turns by the phase 2 pi shift / lambda_j.

An axis's **model file** (``feeddrive model`` format) replaces its default: it is the
axis's *nominal* model, on which its controller is designed and its feedforward runs.  The
simulated **plant** of an axis is its nominal model times the Sec. 4 mismatch
(:data:`feeddrive.experiments.sec4.PERTURBATION`: a real machine is never its model), or the
nominal model itself with ``mismatch="none"``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..experiments.sec4 import PERTURBATION
from ..model_file import load_model
from ..paper import paper_parameters

Y_MASS = 40.0
Y_FRICTION = 1.5
Y_MAGNET_SHIFT = 0.0375 / 4
MISMATCH = ("sec4", "none")
_MAPS = ("cogging", "ripple")


def shift_magnets(params: Mapping[str, Any], shift: float) -> dict[str, Any]:
    """Parameters with the periodic cogging and ripple maps moved by ``shift`` [m]: the map
    of the result at x is the original's at x + shift (harmonic by harmonic)."""
    p = dict(params)
    for m in _MAPS:
        j = 1
        while f"{m}.lambda[{j}]" in p:
            lam = float(p[f"{m}.lambda[{j}]"])
            a, b = float(p[f"{m}.a[{j}]"]), float(p[f"{m}.b[{j}]"])
            phi = 2 * np.pi * shift / lam
            p[f"{m}.a[{j}]"] = a * np.cos(phi) + b * np.sin(phi)
            p[f"{m}.b[{j}]"] = b * np.cos(phi) - a * np.sin(phi)
            j += 1
    return p


def y_axis_parameters(x_params: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The default Y axis derived from the X axis's parameters (module docstring)."""
    p = shift_magnets(dict(x_params or paper_parameters()), Y_MAGNET_SHIFT)
    p["m"] = Y_MASS
    for k in ("friction.F_s", "friction.F_c"):
        p[k] = p[k] * Y_FRICTION
    j = 1
    while f"friction.k[{j}]" in p:
        p[f"friction.k[{j}]"] = p[f"friction.k[{j}]"] * Y_FRICTION
        j += 1
    return p


def mismatched(nominal: Mapping[str, Any]) -> dict[str, Any]:
    """The nominal parameters times the Sec. 4 mismatch."""
    p = dict(nominal)
    for k, f in PERTURBATION.items():
        p[k] = p[k] * f
    return p


@dataclass(frozen=True)
class AxisModel:
    """One axis: its nominal model (controller, feedforward), its plant, where they came from."""

    name: str
    nominal: Mapping[str, Any]
    plant: Mapping[str, Any]
    source: str


def xy_axes(
    x_model: str | Path | None = None, y_model: str | Path | None = None, mismatch: str = "sec4"
) -> tuple[AxisModel, AxisModel]:
    """The X and Y axes: the defaults, or the model files given (ValueError naming the file)."""
    if mismatch not in MISMATCH:
        raise ValueError(f"mismatch = {mismatch!r}: allowed {', '.join(MISMATCH)}")
    x_nom = dict(load_model(x_model).fmu_parameters()) if x_model else dict(paper_parameters())
    y_nom = dict(load_model(y_model).fmu_parameters()) if y_model else y_axis_parameters()
    plant = mismatched if mismatch == "sec4" else dict
    return (
        AxisModel("X", x_nom, plant(x_nom), str(x_model) if x_model else "paper drive"),
        AxisModel(
            "Y",
            y_nom,
            plant(y_nom),
            str(y_model)
            if y_model
            else f"paper drive carrying X: friction x{Y_FRICTION:g}, magnets "
            f"+{Y_MAGNET_SHIFT * 1e3:g} mm",
        ),
    )


def identical_axes(mismatch: str = "sec4") -> tuple[AxisModel, AxisModel]:
    """Two copies of the default X axis (the symmetric table)."""
    x, _ = xy_axes(mismatch=mismatch)
    return x, AxisModel("Y", x.nominal, x.plant, x.source)
