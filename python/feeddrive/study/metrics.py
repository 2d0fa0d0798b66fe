"""The metrics of one study run: tracking error around reversals and overall, and the force
residual of the run's model against a measured run.

- ``reversal_error`` [m]: the peak |x_ref - x| within ``half_width`` of a reference reversal
  (:func:`feeddrive.experiments.tracking_error.summarise`; NaN when the reference has none after
  ``skip_start``);
- ``rms_error``, ``max_error`` [m]: rms and max of |x_ref - x| after ``skip_start``;
- ``force_residual`` [N]: rms of Eq. 1's residual of the run's model along the measured run
  (:func:`feeddrive.residual.force_residual`).

x is the true stage position (not the scale's reading).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..data import Run
from ..experiments.tracking_error import summarise
from ..model_file import ModelFile
from ..residual import force_residual
from .spec import METRICS, Experiment


def tracking_metrics(
    x_ref: np.ndarray, x: np.ndarray, Ts: float, exp: Experiment
) -> dict[str, float]:
    """reversal_error_m, rms_error_m, max_error_m of the error x_ref - x."""
    e = np.asarray(x_ref, float) - np.asarray(x, float)
    s = summarise(e, x_ref, Ts, half_width=exp.half_width, skip_start=exp.skip_start)
    k0 = int(round(exp.skip_start / Ts))
    return {
        "reversal_error_m": float(s.reversal_peak),
        "rms_error_m": float(s.rms),
        "max_error_m": float(np.max(np.abs(e[k0:]))) if len(e) > k0 else float("nan"),
    }


def residual_metric(measured: Run, model: ModelFile) -> float:
    """rms of the model's force residual along the measured run [N]."""
    return force_residual(measured, model).rms


def select(values: Mapping[str, float], metrics: tuple[str, ...]) -> dict[str, float]:
    """The columns of the requested metrics, in the study's order."""
    return {METRICS[m]: float(values[METRICS[m]]) for m in metrics}
