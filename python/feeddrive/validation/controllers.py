"""The closed-loop controller of a run, as a JSON-able spec (the run's sidecar) and back."""
from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..control.design_model import design_model
from ..control.state_space import DEFAULT_MECH_HZ, DEFAULT_OBS_HZ, StateSpaceController
from ..paper import paper_parameters

DESIGN_KEYS = ("m", "Ts", "ripple.c[0]") + tuple(f"current.a[{j}]" for j in range(1, 6)) \
    + tuple(f"current.b[{j}]" for j in range(6))


def state_space_spec(design_params: Mapping[str, float] | None = None, prefilter: str | None = "zpetc",
                     feedforward: str | None = None) -> dict[str, Any]:
    """Spec of the default state-space controller designed on ``design_params`` (paper's)."""
    p = dict(paper_parameters())
    p.update(design_params or {})
    return {"type": "state_space", "design": {k: float(p[k]) for k in DESIGN_KEYS},
            "mech_hz": DEFAULT_MECH_HZ, "mech_zeta": 0.8, "mech_real_hz": 15.0,
            "observer_hz": DEFAULT_OBS_HZ, "observer_zeta": 0.7, "observer_current_poles": [0.2, 0.1],
            "prefilter": prefilter, "feedforward": feedforward, "quantum": 1e-7}


def make_controller(spec: Mapping[str, Any], x_ref: np.ndarray,
                    u_ff: np.ndarray | None = None) -> StateSpaceController:
    """Build the controller a spec describes, for reference ``x_ref`` (sampled at Ts)."""
    if spec.get("type") != "state_space":
        raise ValueError(f"controller type {spec.get('type')!r}: only 'state_space' is known")
    p = dict(paper_parameters())
    p.update(spec.get("design", {}))
    model = design_model(p)
    from ..control.state_space import default_observer_poles, default_poles
    poles = default_poles(model, f_hz=float(spec.get("mech_hz", DEFAULT_MECH_HZ)),
                          zeta=float(spec.get("mech_zeta", 0.8)),
                          f_real_hz=float(spec.get("mech_real_hz", 15.0)))
    obs = default_observer_poles(model, f_hz=float(spec.get("observer_hz", DEFAULT_OBS_HZ)),
                                 zeta=float(spec.get("observer_zeta", 0.7)),
                                 current_poles=tuple(spec.get("observer_current_poles", (0.2, 0.1))))
    return StateSpaceController(model, x_ref, poles=poles, observer_poles=obs, u_ff=u_ff,
                                prefilter=spec.get("prefilter", "zpetc"))
