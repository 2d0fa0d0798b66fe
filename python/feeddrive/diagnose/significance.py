"""Practical significance: a candidate must explain force above the noise floor *and* above a
share of the friction level, on held-out data.

The held-out test of :mod:`scoring` asks whether a candidate explains *something*; it says
nothing about whether that something matters: with a long run it accepts a 0.3 % friction
level change.  Two absolute gates are added, both on the force the candidate removes on
held-out blocks, ``F_expl = sqrt((SSE_before - SSE_heldout) / n)`` [N rms]:

- ``F_expl >= NOISE_FACTOR * floor`` with ``floor`` the rms noise floor
  (:mod:`noise_floor`).  Reason: a perfect model leaves about the floor (1.0-1.5 x measured on
  the FMU's own runs with current noise) and data from another simulator or a real drive add
  integrator, filter and sensor differences of the same order; 3 x keeps a factor 2 above
  what the truth itself leaves.  Not tuned to a generator: it scales with the measured floor.
- ``F_expl >= PRACTICAL_SHARE * F_level`` with ``F_level`` the model's Coulomb level
  ``friction.F_c`` (the rms motor force over the runs when the model has no Coulomb level).
  Reason: guideway friction drifts by several % with temperature, lubrication and wear
  within a working day, so a correction far below that (0.5 % of 21.6 N = 0.11 N) is not
  reproducible from one run to the next; the smallest catalogue effect at its default
  value (frictional lag, C = 1.08e4 N/s) explains about 1 % of F_c on a 6 s sinusoid, twice
  the threshold.

A family that reduces to another in a limit (a load on a spring is a mass far below its
resonance) must also show, on held-out blocks, what it explains *beyond* that family, above
the noise floor (:func:`nested_separable`).

The same two numbers decide the verdict (:func:`verdict`): the final residual's excess over
the floor, ``sqrt(gap^2 - floor^2)``, below either gate is ``explained``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model_file import ModelFile
from ..physics import compile
from ..residual import RunResidual
from .scoring import I_MIN, T_MIN, Score

#: The force a candidate explains must exceed the noise floor's rms by this factor.
NOISE_FACTOR = 3.0
#: ... and this share of the Coulomb friction level.
PRACTICAL_SHARE = 0.005


@dataclass(frozen=True)
class Gate:
    """The two absolute thresholds of a diagnosis [N]."""

    floor_N: float  #: rms noise floor over all runs
    level_N: float  #: the force level the practical share is taken of
    level_source: str

    @property
    def noise_threshold_N(self) -> float:
        return NOISE_FACTOR * self.floor_N

    @property
    def practical_threshold_N(self) -> float:
        return PRACTICAL_SHARE * self.level_N

    @property
    def threshold_N(self) -> float:
        """The larger of the two: a force below it is not named."""
        return max(self.noise_threshold_N, self.practical_threshold_N)

    def to_json(self) -> dict:
        return {
            "noise_factor": NOISE_FACTOR,
            "noise_threshold_N": self.noise_threshold_N,
            "practical_share": PRACTICAL_SHARE,
            "level_N": self.level_N,
            "level_source": self.level_source,
            "practical_threshold_N": self.practical_threshold_N,
            "threshold_N": self.threshold_N,
        }


def make_gate(model: ModelFile, res: list[RunResidual], floor_N: float) -> Gate:
    """The gate of a diagnosis starting from ``model`` (see module docstring)."""
    Fc = float(compile(model).friction.F_c)
    if Fc > 0:
        return Gate(floor_N, Fc, "friction.F_c of the start model")
    F = np.concatenate([q.F_motor[q.valid] for q in res])
    return Gate(floor_N, float(np.sqrt(np.mean(F**2))), "rms motor force over the runs")


def explained_force(s: Score) -> float:
    """Force a candidate removes on held-out blocks, rms over all samples [N]."""
    n = len(s.r_heldout)
    d = float(s.sse_before.sum() - s.sse_after.sum())
    return float(np.sqrt(max(d, 0.0) / n)) if n else 0.0


def passes(s: Score, gate: Gate) -> bool:
    """Held-out significant and above both absolute thresholds."""
    return s.significant and explained_force(s) >= gate.threshold_N


def excess(gap_N: float, floor_N: float) -> float:
    """The part of an rms residual the noise floor does not explain [N]."""
    return float(np.sqrt(max(gap_N**2 - floor_N**2, 0.0)))


def beyond(detail: Score, limit: Score) -> tuple[float, float, float]:
    """What ``detail`` removes on held-out blocks beyond ``limit`` (a family it reduces to in a
    limit, e.g. a load on a spring and a mass): the share of ``limit``'s held-out residual
    energy, the block t statistic of the bounded per-block differences (as :mod:`scoring`'s)
    and the force [N rms over all samples]."""
    sd, sl = detail.sse_after, limit.sse_after
    share = 1.0 - float(sd.sum()) / max(float(sl.sum()), 1e-300)
    d = (sl - sd) / np.maximum(sl + sd, 1e-300)
    s = float(np.std(d, ddof=1)) if len(d) > 1 else 0.0
    t = float(np.mean(d) / (s / np.sqrt(len(d)))) if s > 0 else (np.inf if np.mean(d) > 0 else 0.0)
    n = len(detail.r_heldout)
    force = float(np.sqrt(max(float(sl.sum() - sd.sum()), 0.0) / n)) if n else 0.0
    return share, t, force


def nested_separable(detail: Score, limit: Score, gate: Gate) -> bool:
    """True when held-out data show ``detail`` beyond its limit family ``limit``: it removes
    >= ``I_MIN`` of the residual energy ``limit`` leaves on held-out blocks, consistently over
    blocks (t >= ``T_MIN``) or by a wide margin (more than half of it: the rule of
    :func:`scoring.separable`, for an excitation that rings the load in a few blocks only),
    and that extra force exceeds the noise floor.  Compared on what the limit leaves, not on
    the total: a load whose mass-like part is 99 % of the residual still shows its resonance
    in the remaining 1 %.  This chooses between two families; whether the chosen one is
    named at all is :func:`passes` (its whole explained force against the gate)."""
    share, t, force = beyond(detail, limit)
    return share >= I_MIN and (t >= T_MIN or share > 0.5) and force >= gate.floor_N
