"""Position references sampled at the controller's Ts, and the PRBS excitation.

A :class:`Reference` holds x, v, a at k = 0..n (n controller samples, the run lasts n Ts).
Profiles: :func:`sinusoid`, :func:`point_to_point` (trapezoidal velocity with rest before
and after), :func:`back_and_forth` (constant-speed moves over a stroke, one pair per speed),
:func:`from_positions` (a sampled x_ref, e.g. a measured run's); :func:`reversals` finds
motion reversals and :func:`prbs` is the maximum-length binary sequence added to u.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.signal import max_len_seq


@dataclass
class Reference:
    """x [m], v [m/s], a [m/s^2] of a reference sampled at ``Ts`` [s] (k = 0..n)."""

    Ts: float
    x: np.ndarray
    v: np.ndarray
    a: np.ndarray

    def __post_init__(self) -> None:
        if not self.Ts > 0:
            raise ValueError(f"Reference: Ts = {self.Ts!r} must be > 0")
        self.x, self.v, self.a = (np.asarray(c, dtype=float) for c in (self.x, self.v, self.a))
        if self.x.ndim != 1 or self.x.size < 2:
            raise ValueError("Reference: x must be a 1-D array of at least 2 samples")
        if self.v.shape != self.x.shape or self.a.shape != self.x.shape:
            raise ValueError(
                f"Reference: x, v, a have shapes {self.x.shape}, {self.v.shape}, {self.a.shape}"
            )

    @property
    def time(self) -> np.ndarray:
        """t_k = k Ts [s]."""
        return np.arange(len(self.x)) * self.Ts

    @property
    def n(self) -> int:
        """Number of controller samples (len(x) - 1)."""
        return len(self.x) - 1


def from_positions(x: ArrayLike, Ts: float) -> Reference:
    """A reference from sampled positions; v and a by central differences (np.gradient)."""
    x = np.asarray(x, dtype=float)
    v = np.gradient(x, Ts)
    return Reference(Ts, x, v, np.gradient(v, Ts))


def sinusoid(
    amplitude: float, period: float, centre: float, duration: float, Ts: float = 5e-4
) -> Reference:
    """x_ref = centre - amplitude cos(2 pi t / period): starts at rest at the bottom reversal,
    top reversal at period/2 (the paper's Figs. 14 and 16 look at reversals)."""
    n = int(round(duration / Ts))
    t = np.arange(n + 1) * Ts
    w = 2 * np.pi / period
    return Reference(
        Ts,
        centre - amplitude * np.cos(w * t),
        amplitude * w * np.sin(w * t),
        amplitude * w**2 * np.cos(w * t),
    )


def point_to_point(
    x_start: float, x_end: float, speed: float, accel: float, dwell: float = 0.2, Ts: float = 5e-4
) -> Reference:
    """Trapezoidal move from x_start to x_end at |speed| with |accel|, ``dwell`` [s] at rest
    before and after (triangular when the move is too short to reach ``speed``)."""
    d = x_end - x_start
    s = np.sign(d)
    L = abs(d)
    t_acc = speed / accel
    if accel * t_acc**2 > L:  # triangular profile
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


def back_and_forth(
    speeds: Sequence[float],
    stroke: float = 0.04,
    x0: float = 0.13,
    Ts: float = 5e-4,
    accel: float = 2.0,
    dwell: float = 0.1,
) -> Reference:
    """Forward and backward moves over ``stroke`` [m] at each speed [m/s] (trapezoidal
    velocity, acceleration ``accel``), ``dwell`` [s] at rest before and between moves.

    x is built exactly; v and a by central differences of x.
    """
    pieces = [np.full(int(dwell / Ts), x0)]
    x = x0
    for s in speeds:
        for sign in (1.0, -1.0):
            ta = s / accel
            da = 0.5 * accel * ta**2
            if 2 * da > stroke:
                raise ValueError(
                    f"back_and_forth: speed {s} m/s cannot be reached within {stroke} m"
                )
            tc = (stroke - 2 * da) / s
            T = 2 * ta + tc
            t = np.arange(int(np.ceil(T / Ts)) + 1) * Ts
            t = np.minimum(t, T)
            d = np.where(
                t < ta,
                0.5 * accel * t**2,
                np.where(
                    t < ta + tc, da + s * (t - ta), stroke - 0.5 * accel * np.maximum(T - t, 0) ** 2
                ),
            )
            pieces.append(x + sign * d[1:])
            x = x + sign * stroke
            pieces.append(np.full(int(dwell / Ts), x))
    return from_positions(np.concatenate(pieces), Ts)


def reversals(x_ref: ArrayLike) -> np.ndarray:
    """Indices where the reference velocity changes sign (motion reversals)."""
    dv = np.diff(np.asarray(x_ref, dtype=float))
    sg = np.sign(dv)
    nz = np.nonzero(sg)[0]
    idx = [nz[j + 1] for j in range(len(nz) - 1) if sg[nz[j + 1]] != sg[nz[j]]]
    return np.asarray(idx, dtype=int)


def prbs(
    order: int = 11, amplitude: float = 1.0, offset: float = 0.0, hold: int = 1, periods: int = 1
) -> np.ndarray:
    """Maximum-length pseudo-random binary sequence (scipy.signal.max_len_seq).

    Parameters
    ----------
    order : register length (the paper: 11, period 2**11 - 1 = 2047 bits).
    amplitude, offset : levels offset +- amplitude [V].
    hold : samples per bit (clock divider; 1 = one bit per sample).
    periods : number of repetitions of the full sequence.
    """
    if order < 2 or hold < 1 or periods < 1:
        raise ValueError(
            f"prbs: need order >= 2, hold >= 1, periods >= 1 (got {order}, {hold}, {periods})"
        )
    seq = max_len_seq(order)[0].astype(float)
    u = offset + amplitude * (2.0 * seq - 1.0)
    return np.tile(np.repeat(u, hold), periods)
