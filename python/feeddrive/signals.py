"""Signal helpers shared by identification and diagnosis: run labels, uniform sampling,
and the Savitzky-Golay acceleration with its matched smoothing kernel.

The savgol second-derivative filter c equals the central second difference followed by a
smoothing kernel K (K = double cumulative sum of c, length window - 2, sum 1); filtering the
force side of Eq. 1 with the same K makes both sides see exactly the same averaging.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import savgol_coeffs, savgol_filter

from .data import Run


def run_label(run: Run) -> str:
    """A short name for messages: the file path, else meta['name'], else 'run'."""
    if getattr(run, "path", None) is not None:
        return str(run.path)
    return str(getattr(run, "meta", {}).get("name", "run")) or "run"


def sample_time(time: np.ndarray, rel_tol: float = 0.01, label: str = "run") -> float:
    """Median sample interval; ValueError when the sampling is not uniform within rel_tol."""
    dt = np.diff(np.asarray(time, dtype=float))
    if dt.size == 0:
        raise ValueError(f"{label}: fewer than 2 samples")
    Ts = float(np.median(dt))
    if np.max(np.abs(dt - Ts)) > rel_tol * Ts:
        raise ValueError(
            f"{label}: time is not uniformly sampled (Ts = {Ts:g} s, "
            f"steps from {dt.min():g} to {dt.max():g} s)"
        )
    return Ts


def odd_window(window: int, n: int | None = None) -> int:
    """``window`` made odd (and at most n, when given)."""
    w = int(window) | 1
    if n is not None and w > n:
        w = n if n % 2 else n - 1
    return max(w, 3)


def matched_acceleration(
    x: np.ndarray, Ts: float, window: int, polyorder: int = 3
) -> tuple[np.ndarray, np.ndarray]:
    """Savitzky-Golay acceleration and the smoothing kernel it applies to the true acceleration.

    The savgol second-derivative filter c equals the central second difference followed by
    a smoothing kernel K (K = double cumulative sum of c, length window - 2, sum 1).  Filtering
    the force side of Eq. 1 with the same K makes both sides see exactly the same averaging
    (filtering the force with a deriv-0 savgol filter instead biases m by a few %).
    Returns (a, K); a is NaN within half a window of the ends.
    """
    w = odd_window(window, len(x))
    c = savgol_coeffs(w, min(max(polyorder, 2), w - 1), deriv=2, delta=Ts, use="conv")
    K = np.cumsum(np.cumsum(c))[:-2] * Ts**2
    a = savgol_filter(
        np.asarray(x, dtype=float), w, min(max(polyorder, 2), w - 1), deriv=2, delta=Ts
    )
    h = w // 2
    a[:h] = a[len(a) - h :] = np.nan
    return a, K


def apply_kernel(y: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Centred FIR smoothing of y with kernel K (odd length); NaN where it overhangs the ends."""
    y = np.asarray(y, dtype=float)
    out = np.convolve(y, K, mode="same")
    h = len(K) // 2 + 1
    out[:h] = out[len(out) - h :] = np.nan
    return out
