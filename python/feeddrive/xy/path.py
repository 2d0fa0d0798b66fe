"""The circular test's reference: a circle of radius r at feed F on two axes, with a smooth
start and stop, and the one revolution at constant feed that the evaluation uses.

Angle convention (as the polar plots): theta from the +X axis, counter-clockwise positive;
X = cx + r cos(theta), Y = cy + r sin(theta).  ``ccw`` runs theta upwards, ``cw`` downwards.

Feed profile (ramped feed, the path never leaves the circle): from rest the angular speed
rises to w0 = F / r over ``ramp`` seconds as w0 (t/T - sin(2 pi t/T) / 2 pi) (tangential
acceleration 0 at both ends of the ramp, peak 2 F / T), then stays at w0 for ``settle``
seconds, one full revolution (the evaluated 360 deg, starting at ``eval_start_deg``: 45 deg,
the middle of a quadrant, so every axis reversal at 0, 90, 180, 270 deg is inside it, far
from its ends), and falls back to rest the same way; ``dwell`` seconds at rest open and
close the run (at rest over the ZPETC preview, the controller FMU's inputs and the harness's
pre-filter start alike).
x, v, a of each axis are exact (analytic) at every sample.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..harness.references import Reference

DIRECTIONS = {"ccw": 1.0, "cw": -1.0}
#: peak tangential acceleration of the default ramp [m/s^2] (the ramp lasts >= 0.2 s)
RAMP_ACCEL = 0.5


@dataclass(frozen=True)
class CirclePath:
    """The two axes' references and where the evaluated revolution lies."""

    x: Reference
    y: Reference
    radius: float
    feed: float  #: [m/s]
    direction: str  #: "ccw" or "cw"
    centre: tuple[float, float]
    theta: np.ndarray  #: nominal angle per sample [rad] (unwrapped)
    eval_start: int  #: first sample of the evaluated revolution
    eval_stop: int  #: one past its last sample
    ramp: float  #: [s]

    @property
    def omega(self) -> float:
        """Angular speed at constant feed [rad/s]."""
        return self.feed / self.radius

    @property
    def period(self) -> float:
        """One revolution at constant feed [s]."""
        return 2 * np.pi / self.omega


def default_ramp(feed: float) -> float:
    """Ramp time [s]: peak tangential acceleration :data:`RAMP_ACCEL`, at least 0.2 s."""
    return max(0.2, 2 * feed / RAMP_ACCEL)


def _profile(t: np.ndarray, w0: float, T: float, Tc: float) -> tuple[np.ndarray, ...]:
    """phi, phi', phi'' of the ramp-up (T), constant (Tc), ramp-down (T), hold profile."""
    c = 2 * np.pi / T

    def up(s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return (
            w0 * (s**2 / (2 * T) - (1 - np.cos(c * s)) / (c**2 * T)),
            w0 * (s / T - np.sin(c * s) / (2 * np.pi)),
            w0 / T * (1 - np.cos(c * s)),
        )

    total = w0 * (T + Tc)
    phi, dphi, ddphi = (np.zeros_like(t) for _ in range(3))
    a = t < T
    phi[a], dphi[a], ddphi[a] = up(t[a])
    b = (t >= T) & (t < T + Tc)
    phi[b], dphi[b] = w0 * T / 2 + w0 * (t[b] - T), w0
    d = (t >= T + Tc) & (t < 2 * T + Tc)
    p, dp, ddp = up(2 * T + Tc - t[d])
    phi[d], dphi[d], ddphi[d] = total - p, dp, -ddp
    e = t >= 2 * T + Tc
    phi[e] = total
    return phi, dphi, ddphi


def circle_path(
    radius: float,
    feed: float,
    direction: str = "ccw",
    centre: tuple[float, float] = (0.15, 0.15),
    Ts: float = 5e-4,
    ramp: float | None = None,
    settle: float = 0.25,
    dwell: float = 0.05,
    eval_start_deg: float = 45.0,
) -> CirclePath:
    """The circle's references on X and Y (see the module docstring).

    Parameters
    ----------
    radius : r [m] (> 0).   feed : F [m/s] (> 0).   direction : "ccw" or "cw".
    centre : (cx, cy) [m].   ramp : feed ramp time [s] (default :func:`default_ramp`).
    settle : time at constant feed before the evaluated revolution [s].
    """
    if not (radius > 0 and np.isfinite(radius)):
        raise ValueError(f"circle: radius = {radius!r} must be a finite number > 0 [m]")
    if not (feed > 0 and np.isfinite(feed)):
        raise ValueError(f"circle: feed = {feed!r} must be a finite number > 0 [m/s]")
    if direction not in DIRECTIONS:
        raise ValueError(f"circle: direction = {direction!r}: allowed 'ccw' or 'cw'")
    T = default_ramp(feed) if ramp is None else float(ramp)
    if not T > 0 or settle < 0 or dwell < 0:
        raise ValueError(
            f"circle: ramp = {T}, settle = {settle}, dwell = {dwell}: ramp must be "
            f"> 0, settle and dwell >= 0 [s]"
        )
    s = DIRECTIONS[direction]
    w0 = feed / radius
    t_rev = 2 * np.pi / w0
    Tc = settle + t_rev
    n = int(np.ceil((2 * T + Tc + 2 * dwell) / Ts))
    t = np.arange(n + 1) * Ts
    phi, dphi, ddphi = _profile(np.maximum(t - dwell, 0.0), w0, T, Tc)
    theta_e = np.deg2rad(eval_start_deg)
    theta = theta_e - s * (w0 * T / 2 + w0 * settle) + s * phi
    w, dw = s * dphi, s * ddphi
    ct, st = np.cos(theta), np.sin(theta)
    cx, cy = float(centre[0]), float(centre[1])
    x = Reference(Ts, cx + radius * ct, -radius * st * w, -radius * (ct * w**2 + st * dw))
    y = Reference(Ts, cy + radius * st, radius * ct * w, -radius * (st * w**2 - ct * dw))
    t_e = dwell + T + settle
    k0 = int(np.ceil(t_e / Ts - 1e-9))
    k1 = int(np.floor((t_e + t_rev) / Ts + 1e-9)) + 1
    return CirclePath(
        x=x,
        y=y,
        radius=float(radius),
        feed=float(feed),
        direction=direction,
        centre=(cx, cy),
        theta=theta,
        eval_start=k0,
        eval_stop=min(k1, n + 1),
        ramp=T,
    )
