"""Controllers for the closed-loop harness (pure Python/numpy/scipy, sampled at Ts).

Every controller has ``reset()`` and ``step(x_meas, k) -> u`` [V]; the reference (and the
feedforward) are given as arrays at construction, so ``step`` only indexes them.

- :mod:`design_model`: the sampled design model u -> x (Eq. 2 in series with K_f0/(m s^2)).
- :mod:`state_space`: state feedback + integral action + current estimator (pole placement).
- :mod:`zpetc`: Tomizuka's zero-phase-error tracking pre-filter of the closed loop.
- :mod:`lti`: any linear controller from (x_ref, x_meas) to u, clamp, back-calculation.
- :mod:`pid`: the force-equivalent position PID (optional derivative filter, anti-windup, lead).
- :mod:`feedforward`: inertia, cogging, ripple, offset and friction (static / GMS) feedforward.
- :mod:`margins`: gain / phase / modulus margins from a loop frequency response.
"""

from .design_model import DesignModel, design_model, simulate_linear
from .feedforward import (
    Feedforward,
    FeedforwardOptions,
    feedforward,
    invert_current_loop,
    reference_derivatives,
    static_friction,
)
from .lti import LTIController
from .margins import Margins, loop_margins
from .pid import PID
from .state_space import StateSpaceController, default_observer_poles, default_poles
from .zpetc import ZPETC

__all__ = [
    "DesignModel",
    "design_model",
    "simulate_linear",
    "Feedforward",
    "FeedforwardOptions",
    "feedforward",
    "invert_current_loop",
    "reference_derivatives",
    "static_friction",
    "LTIController",
    "Margins",
    "loop_margins",
    "PID",
    "StateSpaceController",
    "default_observer_poles",
    "default_poles",
    "ZPETC",
]
