"""ISO 230-4 evaluation of a circular test: least-squares centre, radial deviation F,
circular deviation G, circular hysteresis H, and the quadrant glitches at the axis reversals.

Definitions (ISO 230-4, the centre of the paths by least squares, method (b); angles from
the +X axis, counter-clockwise positive):

- *radial deviation* F(theta): distance of the actual path from the centre minus the nominal
  radius R0, positive away from the centre; ``F_max``, ``F_min`` its extremes.
- *circular deviation* G: the minimum radial separation of two circles concentric with the
  least-squares centre that envelop the actual path of one direction: F_max - F_min.
- *circular hysteresis* H: the maximum radial difference between the clockwise and the
  counter-clockwise actual paths, max over theta of |R_cw(theta) - R_ccw(theta)|, both radii
  about one centre (the least-squares centre of the two paths together), each path
  interpolated (linearly, periodic in theta) at the other's sample angles.
- *bidirectional circular deviation* G(b) (the 2005 edition's): the radial separation of
  the two circles about that common centre enveloping both paths.
- *quadrant glitch* (the reversal spike of an axis): at each quadrant transition theta_q =
  0, 90, 180, 270 deg (X reverses at 0 and 180, Y at 90 and 270) the signed extreme of
  F - baseline over the arc from ``lead`` deg before theta_q to ``lag`` deg after it (in the
  direction of travel: the reversing axis sticks, then catches up), the baseline the median
  of F over the arc travelled just before, from 45 deg before theta_q to ``lead`` before it;
  positive outwards.

The least-squares circle minimises sum (|p_i - c| - R)^2 (scipy.optimize.least_squares,
started from the algebraic fit); the path's samples are equally spaced in time at constant
feed, so equally weighted in angle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import least_squares

QUADRANTS = ((0.0, "X"), (90.0, "Y"), (180.0, "X"), (270.0, "Y"))
FLANK_DEG = 45.0
LEAD_DEG = 5.0


@dataclass(frozen=True)
class CircleFit:
    """A least-squares circle: centre [m] and radius [m]."""

    cx: float
    cy: float
    radius: float


def fit_circle(x: ArrayLike, y: ArrayLike) -> CircleFit:
    """The least-squares circle through the points (x, y) (at least 3, not collinear)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.shape != y.shape or x.ndim != 1 or x.size < 3:
        raise ValueError(
            f"fit_circle: x and y must be 1-D of the same length >= 3 (got {x.shape}, {y.shape})"
        )
    mx, my = x.mean(), y.mean()
    u, v = x - mx, y - my  # algebraic (Kasa) fit, centred for conditioning
    A = np.column_stack([u, v, np.ones_like(u)])
    sol, *_ = np.linalg.lstsq(A, u**2 + v**2, rcond=None)
    c0 = np.array([sol[0] / 2, sol[1] / 2])
    r0 = np.sqrt(max(sol[2] + c0 @ c0, 0.0))
    if not (np.isfinite(r0) and r0 > 0):
        raise ValueError("fit_circle: the points do not define a circle")
    scale = r0

    def res(p: np.ndarray) -> np.ndarray:
        return (np.hypot(u - p[0] * scale, v - p[1] * scale) - p[2] * scale) / scale

    fit = least_squares(
        res, np.array([c0[0], c0[1], r0]) / scale, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15
    )
    cx, cy, r = fit.x * scale
    return CircleFit(float(cx + mx), float(cy + my), float(abs(r)))


@dataclass(frozen=True)
class Trace:
    """One direction's actual path about its least-squares centre."""

    direction: str
    x: np.ndarray
    y: np.ndarray
    nominal_radius: float
    fit: CircleFit

    @property
    def theta(self) -> np.ndarray:
        """Angle of each sample about the fitted centre, in [0, 2 pi)."""
        return np.mod(np.arctan2(self.y - self.fit.cy, self.x - self.fit.cx), 2 * np.pi)

    @property
    def F(self) -> np.ndarray:
        """Radial deviation of each sample [m] (about the fitted centre, minus R0)."""
        return np.hypot(self.x - self.fit.cx, self.y - self.fit.cy) - self.nominal_radius

    @property
    def F_max(self) -> float:
        return float(self.F.max())

    @property
    def F_min(self) -> float:
        return float(self.F.min())

    @property
    def G(self) -> float:
        """Circular deviation [m]."""
        F = self.F
        return float(F.max() - F.min())


def trace(x: ArrayLike, y: ArrayLike, nominal_radius: float, direction: str = "ccw") -> Trace:
    """The evaluated path (x, y) [m] of one direction, with its least-squares centre."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    return Trace(direction, x, y, float(nominal_radius), fit_circle(x, y))


def _radius_about(t: Trace, cx: float, cy: float) -> tuple[np.ndarray, np.ndarray]:
    th = np.mod(np.arctan2(t.y - cy, t.x - cx), 2 * np.pi)
    return th, np.hypot(t.x - cx, t.y - cy)


def common_centre(a: Trace, b: Trace) -> CircleFit:
    """The least-squares circle of two paths together (the centre H and G(b) use)."""
    return fit_circle(np.concatenate([a.x, b.x]), np.concatenate([a.y, b.y]))


def hysteresis(cw: Trace, ccw: Trace) -> float:
    """Circular hysteresis H [m] (module docstring)."""
    c = common_centre(cw, ccw)
    (ta, ra), (tb, rb) = _radius_about(cw, c.cx, c.cy), _radius_about(ccw, c.cx, c.cy)
    ia, ib = np.argsort(ta), np.argsort(tb)
    ra_at_b = np.interp(tb, ta[ia], ra[ia], period=2 * np.pi)
    rb_at_a = np.interp(ta, tb[ib], rb[ib], period=2 * np.pi)
    return float(max(np.max(np.abs(ra_at_b - rb)), np.max(np.abs(rb_at_a - ra))))


def bidirectional_deviation(cw: Trace, ccw: Trace) -> float:
    """G(b) [m]: both paths' radii about the common centre, max - min."""
    c = common_centre(cw, ccw)
    r = np.concatenate([_radius_about(cw, c.cx, c.cy)[1], _radius_about(ccw, c.cx, c.cy)[1]])
    return float(r.max() - r.min())


@dataclass(frozen=True)
class Glitch:
    """The reversal spike at one quadrant transition."""

    angle_deg: float
    axis: str  #: the axis that reverses there
    height: float  #: [m], signed, positive outwards


def glitch_window(radius: float, feed: float, duration: float = 0.4) -> float:
    """The glitch arc after a reversal [deg]: the angle travelled in ``duration`` seconds
    (the friction transient of a reversal; Sec. 4's window), within 5..40 deg."""
    return float(np.clip(np.rad2deg(feed / radius * duration), 5.0, 40.0))


def glitches(t: Trace, lag_deg: float, lead_deg: float = LEAD_DEG) -> list[Glitch]:
    """The four quadrant glitches of a trace (module docstring)."""
    if not (0 < lead_deg < FLANK_DEG and 0 < lag_deg < FLANK_DEG):
        raise ValueError(
            f"glitches: lead {lead_deg} and lag {lag_deg} deg must be in (0, {FLANK_DEG})"
        )
    s = -1.0 if t.direction == "cw" else 1.0
    th, F = np.rad2deg(t.theta), t.F
    out = []
    for q, axis in QUADRANTS:
        d = s * ((th - q + 180.0) % 360.0 - 180.0)  # travelled past theta_q [deg]
        inner, before = (d >= -lead_deg) & (d <= lag_deg), (d >= -FLANK_DEG) & (d < -lead_deg)
        if not inner.any() or not before.any():
            raise ValueError(f"glitches: the path has no samples near {q:g} deg")
        dev = F[inner] - np.median(F[before])
        out.append(Glitch(q, axis, float(dev[np.argmax(np.abs(dev))])))
    return out
