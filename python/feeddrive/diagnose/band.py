"""The acceleration estimator's band, and a second look at a mass-like residual through a
wider one.

The residual's acceleration is the Savitzky-Golay second derivative of the position; the
smoothing kernel K it applies (``signals.matched_acceleration``) is a low-pass: with the
default 20 ms window (41 samples at 0.5 ms) it passes 6 dB less at 47 Hz and little above
~100 Hz.  A load on a spring acts as a mass below its resonance and shows its own dynamics
only near and above it; above the band K hides them and the load is taken for a mass.
Before a mass change is named, the diagnosis therefore looks at the same runs through a
short window (``WIDE_WINDOW_S``, 5.5 ms, -6 dB at ~180 Hz), with its own noise floor (the
quantisation noise of a short differentiator is ~27 x larger):

- when the load's resonance shows there beyond the mass (``significance.nested_separable``)
  and passes that band's gate, ``compliance`` is named from the wide-band fit;
- when it shows some of it (``TRACE``: a held-out share of what the mass leaves,
  consistent over blocks) but cannot confirm it, nothing is named: the verdict names the band of the data and the
  resonance it glimpsed instead of a mass;
- else (no trace of dynamics: a rigid mass error, or a load far above both bands) the mass
  is named.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..data import Run
from ..model_file import ModelFile
from ..physics import compile
from ..residual import RunResidual, residuals
from .candidates import CANDIDATES
from .context import Context
from .noise_floor import noise_floor
from .scoring import T_MIN, Score, score
from .significance import Gate, beyond, make_gate, nested_separable, passes

#: Window of the wide-band look [s] (11 samples at 0.5 ms).
WIDE_WINDOW_S = 0.0055
#: Attenuation that bounds a kernel's band (half the amplitude).
BAND_GAIN = 0.5
#: Held-out share of what the mass leaves that the wide-band resonance must remove, with a
#: block t >= T_MIN, to count as a trace of a load (the share I_MIN that names an effect).
TRACE = 0.05


def kernel_band_hz(K: np.ndarray, Ts: float, gain: float = BAND_GAIN) -> float:
    """The lowest frequency [Hz] at which the smoothing kernel ``K`` passes ``gain`` of DC."""
    f = np.linspace(0.0, 0.5 / Ts, 2001)
    H = np.abs(np.exp(-2j * np.pi * np.outer(f, np.arange(len(K))) * Ts) @ K) / abs(K.sum())
    below = np.flatnonzero(H < gain)
    return float(f[below[0]]) if below.size else 0.5 / Ts


def residual_band_hz(res: list[RunResidual]) -> float:
    """The band [Hz] the acceleration estimate of a set of residuals resolves (the narrowest
    over the runs)."""
    return min(kernel_band_hz(q.K, q.Ts) for q in res)


@dataclass
class WideBand:
    """The wide-band look at a mass-like residual."""

    band_Hz: float  #: the diagnosis window's band
    wide_band_Hz: float  #: the wide window's band
    window: int  #: wide window [samples]
    context: Context
    gate: Gate
    compliance: Score | None  #: the best compliance variant on the wide band
    mass: Score
    share_beyond: float  #: held-out share of the mass's residual it removes
    t_beyond: float
    force_beyond_N: float
    confirmed: bool  #: compliance shows beyond the mass and passes the gate

    @property
    def trace(self) -> bool:
        """The resonance shows beyond the mass on held-out blocks (>= ``TRACE`` of what the
        mass leaves, consistently: block t >= ``T_MIN``) but is not confirmed (its force is
        below that band's floor or gate)."""
        return (
            not self.confirmed
            and self.compliance is not None
            and self.share_beyond >= TRACE
            and self.t_beyond >= T_MIN
        )

    def to_json(self) -> dict:
        c = self.compliance
        return {
            "band_Hz": self.band_Hz,
            "wide_band_Hz": self.wide_band_Hz,
            "wide_window_samples": self.window,
            "wide_noise_floor_N": self.gate.floor_N,
            "wide_threshold_N": self.gate.threshold_N,
            "compliance_variant": c.variant.label if c else None,
            "heldout_share_beyond_mass": self.share_beyond,
            "t_beyond_mass": self.t_beyond,
            "force_beyond_mass_N": self.force_beyond_N,
            "confirmed": self.confirmed,
        }


def wide_band(
    runs: list[Run],
    model: ModelFile,
    res: list[RunResidual],
    n_blocks: int,
    force_gain: float | None = None,
    *,
    load: str,
    limit: str,
) -> WideBand | None:
    """The candidate family ``load`` (a load on a spring) against the family ``limit`` it
    reduces to (a mass change) on the runs' residual through ``WIDE_WINDOW_S`` (module
    docstring; :func:`feeddrive.effects.nesting`); None when the wide window is not shorter
    than the one in use."""
    Ts = min(q.Ts for q in res)
    w = int(round(WIDE_WINDOW_S / Ts)) | 1
    if w >= min(len(q.K) for q in res) + 2:
        return None
    wres = residuals(runs, model, window=w, force_gain=force_gain)
    plant = compile(model)
    floors = [noise_floor(run, q, plant, force_gain) for run, q in zip(runs, wres, strict=True)]
    floor_N = float(
        np.sqrt(
            np.mean(
                np.concatenate([f.sigma[q.valid] ** 2 for f, q in zip(floors, wres, strict=True)])
            )
        )
    )
    gate = make_gate(model, wres, floor_N)
    ctx = Context(wres, model, n_blocks=n_blocks)
    sm = score(ctx, CANDIDATES[limit](ctx)[0])
    scores = [score(ctx, v) for v in CANDIDATES[load](ctx)]
    sc = max(scores, key=lambda s: s.improvement) if scores else None
    share, t, force = beyond(sc, sm) if sc is not None else (0.0, 0.0, 0.0)
    ok = sc is not None and nested_separable(sc, sm, gate) and passes(sc, gate)
    return WideBand(
        band_Hz=residual_band_hz(res),
        wide_band_Hz=residual_band_hz(wres),
        window=w,
        context=ctx,
        gate=gate,
        compliance=sc,
        mass=sm,
        share_beyond=share,
        t_beyond=t,
        force_beyond_N=force,
        confirmed=ok,
    )
