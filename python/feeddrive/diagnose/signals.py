"""Signal helpers of the diagnosis: sampling checks and the matched acceleration filter.

The Savitzky-Golay second-derivative filter c equals the central second difference followed
by a smoothing kernel K (K = double cumulative sum of c, length window - 2, sum 1); filtering
the force side of Eq. 1 with the same K makes both sides see exactly the same averaging.
(The same construction as ``feeddrive.identify``'s; kept here so that the diagnosis does not
depend on that package's private helpers.)
"""
from __future__ import annotations

import numpy as np
from scipy.signal import savgol_coeffs, savgol_filter

from ..data import Run


def run_label(run: Run) -> str:
    """A short name for messages: the file path, else meta['name'], else 'run'."""
    if run.path is not None:
        return str(run.path)
    return str((run.meta or {}).get("name", "run")) or "run"


def sample_time(time: np.ndarray, rel_tol: float = 0.01, label: str = "run") -> float:
    """Median sample interval; ValueError naming the run when sampling is not uniform."""
    dt = np.diff(np.asarray(time, dtype=float))
    if dt.size == 0:
        raise ValueError(f"{label}: fewer than 2 samples")
    Ts = float(np.median(dt))
    if np.max(np.abs(dt - Ts)) > rel_tol * Ts:
        raise ValueError(f"{label}: column 'time' is not uniformly sampled (Ts = {Ts:g} s, "
                         f"steps from {dt.min():g} to {dt.max():g} s)")
    return Ts


def odd_window(window: int, n: int | None = None) -> int:
    """``window`` made odd (and at most n, when given), at least 5."""
    w = int(window) | 1
    if n is not None and w > n:
        w = n if n % 2 else n - 1
    return max(w, 5)


def matched_acceleration(x: np.ndarray, Ts: float, window: int, polyorder: int = 3
                         ) -> tuple[np.ndarray, np.ndarray]:
    """Savitzky-Golay acceleration (NaN within half a window of the ends) and its kernel K."""
    w = odd_window(window, len(x))
    po = min(max(polyorder, 2), w - 1)
    c = savgol_coeffs(w, po, deriv=2, delta=Ts, use="conv")
    K = np.cumsum(np.cumsum(c))[:-2] * Ts**2
    a = savgol_filter(np.asarray(x, dtype=float), w, po, deriv=2, delta=Ts)
    h = w // 2
    a[:h] = a[len(a) - h:] = np.nan
    return a, K


def apply_kernel(y: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Centred FIR smoothing of y with kernel K (odd length); NaN where it overhangs the ends."""
    out = np.convolve(np.asarray(y, dtype=float), K, mode="same")
    h = len(K) // 2 + 1
    out[:h] = out[len(out) - h:] = np.nan
    return out


def zoh_midpoint(f: np.ndarray) -> np.ndarray:
    """(f[k-1] + f[k]) / 2: what the central second difference of x sees at sample k of a
    force held over [t_k, t_k+1) (sampled current); f[0] kept."""
    f = np.asarray(f, dtype=float)
    out = f.copy()
    out[1:] = 0.5 * (f[1:] + f[:-1])
    return out
