"""Tracking-error metrics around motion reversals and elsewhere."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..harness.references import reversals


@dataclass
class ErrorSummary:
    """Peak |error| near reversals, the error band elsewhere and the overall rms [m]."""

    reversal_peak: float
    band: float
    rms: float
    reversal_peaks: list[float]

    def as_um(self) -> dict[str, float]:
        return {
            "reversal_peak_um": self.reversal_peak * 1e6,
            "band_um": self.band * 1e6,
            "rms_um": self.rms * 1e6,
        }


def reversal_mask(
    x_ref: np.ndarray, Ts: float, half_width: float = 0.25, skip_start: float = 0.5
) -> tuple[np.ndarray, np.ndarray]:
    """Boolean masks (near a reversal, elsewhere) over the samples of ``x_ref``.

    ``half_width`` [s] either side of each reversal of the reference; the first ``skip_start``
    seconds (start-up transient from rest) belong to neither.
    """
    n = len(x_ref)
    near = np.zeros(n, bool)
    w = int(round(half_width / Ts))
    for r in reversals(x_ref):
        near[max(0, r - w) : min(n, r + w + 1)] = True
    start = np.zeros(n, bool)
    start[: int(round(skip_start / Ts))] = True
    near &= ~start
    return near, ~near & ~start


def summarise(
    error: np.ndarray,
    x_ref: np.ndarray,
    Ts: float,
    half_width: float = 0.25,
    skip_start: float = 0.5,
) -> ErrorSummary:
    """Summary of a tracking (or model-vs-measurement) error signal."""
    e = np.abs(np.asarray(error, float))
    _near, far = reversal_mask(x_ref, Ts, half_width, skip_start)
    w = int(round(half_width / Ts))
    peaks = [
        float(e[max(0, r - w) : r + w + 1].max()) for r in reversals(x_ref) if r * Ts >= skip_start
    ]
    valid = ~np.zeros(len(e), bool)
    valid[: int(round(skip_start / Ts))] = False
    return ErrorSummary(
        reversal_peak=max(peaks) if peaks else float("nan"),
        band=float(e[far].max()) if far.any() else float("nan"),
        rms=float(np.sqrt(np.mean(np.asarray(error)[valid] ** 2))),
        reversal_peaks=peaks,
    )
