"""Reference trajectories sampled at Ts: position and its first two derivatives."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Reference:
    """x, v, a of a reference sampled at ``Ts`` (k = 0..n)."""

    Ts: float
    x: np.ndarray
    v: np.ndarray
    a: np.ndarray

    @property
    def time(self) -> np.ndarray:
        return np.arange(len(self.x)) * self.Ts

    @property
    def n(self) -> int:
        """Number of controller samples (len(x) - 1)."""
        return len(self.x) - 1


def sinusoid(amplitude: float, period: float, centre: float, duration: float,
             Ts: float = 5e-4) -> Reference:
    """x_ref = centre - amplitude cos(2 pi t / period): starts at rest at the bottom reversal,
    top reversal at period/2 (the paper's Figs. 14 and 16 look at reversals)."""
    n = int(round(duration / Ts))
    t = np.arange(n + 1) * Ts
    w = 2 * np.pi / period
    return Reference(Ts, centre - amplitude * np.cos(w * t), amplitude * w * np.sin(w * t),
                     amplitude * w**2 * np.cos(w * t))


def constant_speed(x_start: float, x_end: float, speed: float, accel: float, dwell: float = 0.2,
                   Ts: float = 5e-4) -> Reference:
    """Trapezoidal move from x_start to x_end at |speed| with |accel|, with rest before/after."""
    d = x_end - x_start
    s = np.sign(d)
    L = abs(d)
    t_acc = speed / accel
    if accel * t_acc**2 > L:          # triangular profile
        t_acc = np.sqrt(L / accel)
        speed = accel * t_acc
    t_cruise = (L - accel * t_acc**2) / speed
    T = dwell + 2 * t_acc + t_cruise + dwell
    n = int(np.ceil(T / Ts))
    t = np.arange(n + 1) * Ts - dwell
    v = np.clip(np.minimum(accel * t, accel * (2 * t_acc + t_cruise - t)), 0.0, speed)
    v[t < 0] = 0.0
    a = np.gradient(v, Ts)
    x = x_start + s * np.concatenate([[0.0], np.cumsum((v[1:] + v[:-1]) / 2 * Ts)])
    return Reference(Ts, x, s * v, s * a)


def reversals(x_ref: np.ndarray) -> np.ndarray:
    """Indices where the reference velocity changes sign (motion reversals)."""
    dv = np.diff(x_ref)
    sg = np.sign(dv)
    nz = np.nonzero(sg)[0]
    idx = [nz[j + 1] for j in range(len(nz) - 1) if sg[nz[j + 1]] != sg[nz[j]]]
    return np.asarray(idx, dtype=int)
