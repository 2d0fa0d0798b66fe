"""Model-based feedforward u_ff[k] for a whole reference trajectory (computed once, vectorised).

The force the motor must supply to follow x_ref (Eq. 1 with F_e = 0) is

    F_ff = m a_ref + F_cg(x_ref) + F_f(v_ref) + F_offset

and the voltage is u_ff = F_ff / (K_f(x_ref) G(1)): ripple compensation divides by the
position-dependent force constant K_f(x_ref) (Eq. 7) instead of K_f0.  With
``current_loop="inverse"`` the current i_ff = F_ff / K_f(x_ref) is instead passed through
the exact inverse of Eq. 2 (its zero -0.7461 is inside the unit circle), using d0 samples of
reference preview, so that the current loop delivers i_ff on time.

Friction models:

- ``"static"``: Eq. 12 as a memoryless function of v with the sign regularised,
  F = S(|v|) tanh(v / v_eps) + sigma2 v, v_eps = 0.3 mm/s (about V_s/10) by default: the
  plain sgn(v_ref) jumps by 2 F_s at a reversal and excites the loop.  |F| is
  within 0.5 % of the steady curve for |v| >= 3 v_eps, F(0) = 0,
  dF/dv(0) = S(0)/v_eps + sigma2.
- ``"gms"``: the GMS model (:mod:`feeddrive.physics.friction_gms`) driven by (x_ref, v_ref).

Python simulation of the default state-space loop on the design model with the paper's GMS
friction as plant (5 mm / 6 s sine, 100 nm resolution), peak error at the reversal: ~23 um
without feedforward; "static" ~20 um (two peaks of opposite sign, -20/+19 um; v_eps =
0.1 mm/s gives ~37 um, 1 mm/s ~16 um); "gms" on the plant's own parameters ~1.4 um with
current_loop="dc", ~0.07 um with "inverse" (unrealistically good: the plant is the model); "gms" on
parameters off by 5-20 % ~3.5 um.

Every term uses the *nominal* parameters passed in (FMU names, SI; the effect switches of that
dict respected, as :func:`feeddrive.physics.compile` applies them), which need not equal the
simulated plant's.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal

from ..physics import GMSParameters, PlantParameters, compile, gms_force

DEFAULT_V_EPS = 3e-4  #: m/s (~ V_s/10), regularisation speed of the static-friction sign


#: the friction terms of the feedforward
FrictionFeedforward = Literal["none", "static", "gms"]


@dataclass(frozen=True)
class FeedforwardOptions:
    """Which feedforward terms to use.

    inertia : m a_ref (off by default: with a ZPETC pre-filter the linear loop already
        tracks; the inertia term then only duplicates it).
    cogging : F_cg(x_ref).   ripple : divide by K_f(x_ref) (else by K_f0 = ripple.c[0]).
    friction : "none", "static" (regularised Tustin/Stribeck curve) or "gms".
    v_eps : regularisation speed of "static" [m/s].
    offset : the compiled plant's constant offset force (offset.F, 0 with its effect off).
    current_loop : "dc" (divide by G(1)) or "inverse" (exact inverse of Eq. 2 with preview).
    """

    inertia: bool = False
    cogging: bool = True
    ripple: bool = True
    friction: FrictionFeedforward = "gms"
    v_eps: float = DEFAULT_V_EPS
    offset: bool = True
    current_loop: Literal["dc", "inverse"] = "dc"


@dataclass
class Feedforward:
    """Result: u [V] per sample, the force terms [N], K_f used [N/A], G(1) [A/V]."""

    u: np.ndarray
    forces: dict[str, np.ndarray] = field(default_factory=dict)
    K_f: np.ndarray | None = None
    G1: float = 1.0


def reference_derivatives(x_ref: ArrayLike, Ts: float) -> tuple[np.ndarray, np.ndarray]:
    """v_ref, a_ref by second-order finite differences (``numpy.gradient``)."""
    x = np.asarray(x_ref, dtype=float)
    v = np.gradient(x, Ts)
    return v, np.gradient(v, Ts)


def static_friction(
    v: ArrayLike, prm: GMSParameters, v_eps: float = DEFAULT_V_EPS, x: ArrayLike | None = None
) -> np.ndarray:
    """Regularised Eq. 12: S(|v|) tanh(v / v_eps) + sigma2 v [N] (asymmetry by side of v;
    the level at x, p(x) S, with ``position_friction`` and the positions given)."""
    if not v_eps > 0:
        raise ValueError(f"feedforward.py: v_eps must be > 0 (got {v_eps})")
    v = np.asarray(v, dtype=float)
    return prm.level(v, x) * np.tanh(v / v_eps) + prm.viscous(v)


def invert_current_loop(
    i_ff: ArrayLike, params: Mapping[str, float] | PlantParameters
) -> np.ndarray:
    """u such that Eq. 2 gives exactly i_ff (needs d0 samples of preview; i_ff held at the end).

    G = z^-d0 B'(z^-1)/A(z^-1), u[k] = (A/B')(z^-1) i_ff[k + d0].  B' must be minimum phase.
    """
    i = np.asarray(i_ff, dtype=float)
    P = params if isinstance(params, PlantParameters) else compile(params)
    num, den = P.current.polynomials()
    d0 = int(np.argmax(num != 0.0))
    Bp = num[d0:]
    zeros = np.roots(Bp) if len(Bp) > 1 else np.zeros(0)
    if np.any(np.abs(zeros) >= 1.0):
        raise ValueError(
            f"feedforward.py: current.b gives non-minimum-phase zeros {zeros}; "
            "use current_loop='dc'"
        )
    ip = np.concatenate((i, np.full(d0, i[-1])))
    zi = signal.lfilter_zi(den, Bp) * i[0] if max(len(den), len(Bp)) > 1 else None
    if zi is None:
        return (ip * den[0] / Bp[0])[d0:]
    u, _ = signal.lfilter(den, Bp, ip, zi=zi)
    return u[d0:]


def feedforward(
    x_ref: ArrayLike,
    Ts: float,
    params: Mapping[str, float],
    options: FeedforwardOptions = FeedforwardOptions(),
    v_ref: ArrayLike | None = None,
    a_ref: ArrayLike | None = None,
) -> Feedforward:
    """Feedforward voltage for the reference ``x_ref`` sampled at ``Ts``.

    Parameters
    ----------
    x_ref : reference positions [m].  v_ref, a_ref : its derivatives (default: finite
        differences; pass the analytic ones when known).
    params : nominal FMU-named parameters (SI).
    options : :class:`FeedforwardOptions`.
    """
    x = np.asarray(x_ref, dtype=float)
    if x.ndim != 1 or x.size < 2:
        raise ValueError("feedforward.py: x_ref must be a 1-D array of >= 2 samples")
    v_fd, a_fd = reference_derivatives(x, Ts)
    v = v_fd if v_ref is None else np.asarray(v_ref, dtype=float)
    a = a_fd if a_ref is None else np.asarray(a_ref, dtype=float)
    if v.shape != x.shape or a.shape != x.shape:
        raise ValueError("feedforward.py: v_ref and a_ref must have the shape of x_ref")

    P = compile(params)
    forces: dict[str, np.ndarray] = {}
    if options.inertia:
        forces["inertia"] = P.m * a
    if options.cogging:
        forces["cogging"] = P.F_cg(x)
    if options.offset and P.F_offset != 0.0:
        forces["offset"] = np.full_like(x, P.F_offset)
    if options.friction == "static":
        forces["friction"] = static_friction(v, P.friction, options.v_eps, x)
    elif options.friction == "gms":
        forces["friction"] = gms_force(x, v, Ts, P.friction)
    elif options.friction != "none":
        raise ValueError(
            f"feedforward.py: friction must be 'none', 'static' or 'gms', got {options.friction!r}"
        )
    total = np.zeros_like(x)
    for f in forces.values():
        total = total + f
    forces["total"] = total
    K_f = P.K_f(x) if options.ripple else np.full_like(x, P.ripple.c[0])
    G1 = P.current.G1
    if options.current_loop == "dc":
        u = total / (K_f * G1)
    elif options.current_loop == "inverse":
        u = invert_current_loop(total / K_f, P)
    else:
        raise ValueError(
            f"feedforward.py: current_loop must be 'dc' or 'inverse', got {options.current_loop!r}"
        )
    return Feedforward(u=u, forces=forces, K_f=K_f, G1=G1)
