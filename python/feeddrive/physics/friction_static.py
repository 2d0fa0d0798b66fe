"""The memoryless alternative to the GMS (``prerolling`` off, the plant structure
:attr:`~feeddrive.effects.Structure.SLIP_ELEMENTS` off): Eq. 12 with Karnopp stiction.

Sliding, friction is s(v) + sigma2 v (:func:`.friction_curves.steady_friction`, per side);
at rest it balances the applied force F_app while |F_app| is below the break-away level
F_s of the side of F_app.  The FMU locates v = 0 by events (fmu_src/physics/friction_static.c);
on measured data the stage counts as at rest where |v| < ``v_stick``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .friction_gms import GMSParameters

#: Below this speed [m/s] measured motion counts as at rest.
DEFAULT_V_STICK = 2e-5


def karnopp_friction(
    v: ArrayLike,
    F_app: ArrayLike,
    prm: GMSParameters,
    v_stick: float = DEFAULT_V_STICK,
    x: ArrayLike | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Friction [N] along a motion and the stuck mask: F = F_app where |v| < v_stick and
    |F_app| < F_s (side of F_app), else the steady sliding friction of v.  With the
    positions ``x`` the levels are those at x (``position_friction``: p(x) F_s, p(x) S)."""
    v = np.asarray(v, dtype=float)
    F_app = np.asarray(F_app, dtype=float)
    stuck = (np.abs(v) < v_stick) & (np.abs(F_app) < prm.break_away(F_app, x))
    return np.where(stuck, F_app, prm.steady(v, x)), stuck
