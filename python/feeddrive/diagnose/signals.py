"""Signal helpers of the diagnosis: the shared ones (feeddrive.signals) and the zero-order-hold
midpoint of a sampled force."""
from __future__ import annotations

import numpy as np

from ..signals import apply_kernel, matched_acceleration, odd_window, run_label, sample_time  # noqa: F401


def zoh_midpoint(f: np.ndarray) -> np.ndarray:
    """(f[k-1] + f[k]) / 2: what the central second difference of x sees at sample k of a
    force held over [t_k, t_k+1) (sampled current); f[0] kept."""
    f = np.asarray(f, dtype=float)
    out = f.copy()
    out[1:] = 0.5 * (f[1:] + f[:-1])
    return out
