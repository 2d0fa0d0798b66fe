"""What a validated study is: the parameters varied (:class:`ParameterSpec`), the closed loop
every run simulates (:class:`Experiment`) and the whole :class:`Study`, with the metrics a
study may ask for."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import scipy.stats

from ..harness.sensors import Sensors
from ..model_file import ModelFile

#: Metric names a study may ask for, and the table column each gives.
METRICS: dict[str, str] = {
    "reversal_error": "reversal_error_m",
    "rms_error": "rms_error_m",
    "max_error": "max_error_m",
    "force_residual": "force_residual_N",
    "circular_deviation": "G_m",
    "hysteresis": "H_m",
    "max_glitch": "max_glitch_m",
}
#: metrics of the circle experiment (the others need a reference and a controller)
CIRCLE_METRICS = ("circular_deviation", "hysteresis", "max_glitch")


@dataclass(frozen=True)
class ParameterSpec:
    """How one FMU parameter varies: a range, a scipy.stats distribution, or values."""

    name: str
    base: float
    low: float | None = None
    high: float | None = None
    distribution: str | None = None
    dist_args: Mapping[str, float] = field(default_factory=dict)
    values: tuple[float, ...] | None = None

    def frozen_distribution(self) -> Any:
        """The scipy.stats frozen distribution (``uniform`` over the range when a range)."""
        if self.distribution is not None:
            return getattr(scipy.stats, self.distribution)(**self.dist_args)
        if self.low is None or self.high is None:
            raise ValueError(f"parameter {self.name}: a list of values has no distribution")
        return scipy.stats.uniform(loc=self.low, scale=self.high - self.low)


@dataclass(frozen=True)
class Experiment:
    """The closed loop every run of a study simulates (the plant parameters vary)."""

    reference: Mapping[str, Any]
    controller: Mapping[str, Any]
    sensors: Sensors
    F_load: float = 0.0
    tolerance: float = 1e-6
    skip_start: float = 0.0
    half_width: float = 0.25
    measured: Path | None = None
    #: the circular test (radius, feed, feedforward, directions, y_axis) instead of a
    #: reference and a controller (which are then empty)
    circle: Mapping[str, Any] | None = None


@dataclass(frozen=True)
class Study:
    """A validated study (see the module docstring)."""

    source: str
    name: str
    model: ModelFile
    experiment: Experiment
    parameters: tuple[ParameterSpec, ...]
    design: Mapping[str, Any]
    metrics: tuple[str, ...]
    batch_size: int | None = None
    text: str = ""  #: the file's canonical JSON (a study's identity for --resume)

    @property
    def parameter_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    @property
    def metric_columns(self) -> tuple[str, ...]:
        return tuple(METRICS[m] for m in self.metrics)
