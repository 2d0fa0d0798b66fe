"""The diagnosis record: the ordered steps, the stop record, the start and final models,
and the localisation summaries of the start and final residuals."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..model_file import ModelFile
from ..residual import RunResidual
from .localise import localise, spatial_spectrum, spectral_peaks
from .noise_floor import NoiseFloor, floor_table
from .significance import Gate
from .step import Step
from .timeaxis import time_axis


@dataclass
class Diagnosis:
    """The ordered steps, the stop record, the start and final models."""

    steps: list[Step]
    stop: dict
    model_start: ModelFile
    model: ModelFile
    runs: list[str]
    notes: list[str]
    residual_start: list[RunResidual] = field(default_factory=list, repr=False)
    residual_final: list[RunResidual] = field(default_factory=list, repr=False)
    floors: list[NoiseFloor] = field(default_factory=list, repr=False)
    gate: Gate | None = None
    verdict: dict = field(default_factory=dict)
    #: the start model with only the confirmed steps (model.json); ``model`` has every fit
    model_confirmed: ModelFile | None = None
    #: per step: confirmed or not and why (:mod:`confirmed`), and the confirmed model's gap
    confirmation: dict = field(default_factory=dict)

    @property
    def named(self) -> list[str]:
        """Effects added, in order."""
        return [s.effect for s in self.steps if s.effect is not None]

    def to_json(self) -> dict:
        return {
            "schema": "feeddrive.diagnosis/2",
            "runs": self.runs,
            "model_start": self.model_start.name,
            "notes": self.notes,
            "verdict": self.verdict,
            "noise_floor": floor_table(self.residual_start, self.floors) if self.floors else {},
            "initial_friction": {
                q.name: q.start.to_json(q.Ts) for q in self.residual_start if q.start is not None
            },
            "significance": self.gate.to_json() if self.gate else {},
            "localisation_start": localisation_summary(self.residual_start, self.floors),
            "steps": [s.to_json() for s in self.steps],
            "stop": self.stop,
            "final_model": self.model.name,
            "confirmation": self.confirmation,
            "localisation_final": localisation_summary(self.residual_final, self.floors),
        }


def localisation_summary(res: list[RunResidual], floors: list[NoiseFloor] | None = None) -> dict:
    """Regime and position table of a residual, the peaks of its spatial spectra and its
    time axis (per time block of each run, with the noise floor when ``floors`` are given)."""
    if not res:
        return {}
    loc = localise(res)
    loc["time"] = time_axis(res, [f.sigma for f in floors] if floors else None)
    peaks = {}
    for weight, key in ((None, "cogging_like_N"), ("i", "ripple_like_N_per_A")):
        if weight == "i" and any(q.i is None for q in res):
            continue
        lams, amps = spatial_spectrum(res, weight=weight)
        peaks[key] = [
            {"wavelength_m": lam, "amplitude": a}
            for lam, a in spectral_peaks(lams, amps, n_peaks=3)
        ]
    loc["spectrum_peaks"] = peaks
    return loc
