"""Memoryless friction curves of Eqs. 10 and 12 in SI (the GMS steady state)."""
from __future__ import annotations

import numpy as np


def stribeck_level(speed: np.ndarray | float, F_s: float, F_c: float, V_s: float,
                   delta: float) -> np.ndarray:
    """S(|v|) = F_c + (F_s - F_c) exp(-|v/V_s|^delta) [N]; S(0) = F_s."""
    s = np.abs(np.asarray(speed, dtype=float))
    return F_c + (F_s - F_c) * np.exp(-np.power(s / V_s, delta))


def steady_friction(v: np.ndarray | float, F_s: float, F_c: float, V_s: float,
                    delta: float, sigma2: float) -> np.ndarray:
    """Steady sliding friction s(v) + sigma2 v (Eq. 12) [N]; 0 at v = 0 (sgn(0) = 0)."""
    v = np.asarray(v, dtype=float)
    return np.sign(v) * stribeck_level(v, F_s, F_c, V_s, delta) + sigma2 * v
