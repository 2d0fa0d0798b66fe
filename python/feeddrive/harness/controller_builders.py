"""Spec -> controller for each registry type (:mod:`.controllers`), the protocol every
controller meets and the wrapper that adds one sample of computation delay."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import fields
from typing import Any, Protocol

import numpy as np

from ..control.design_model import design_model
from ..control.feedforward import FeedforwardOptions, feedforward
from ..control.lti import LTIController
from ..control.pid import PID, PIDSettings
from ..control.state_space import (
    DEFAULT_MECH_HZ,
    DEFAULT_MECH_REAL_HZ,
    DEFAULT_MECH_ZETA,
    DEFAULT_OBS_CURRENT,
    DEFAULT_OBS_HZ,
    DEFAULT_OBS_ZETA,
    StateSpaceController,
    default_observer_poles,
    default_poles,
)
from ..paper import paper_parameters
from .controller_specs import DESIGN_KEYS
from .lti_realisation import lti_realisation
from .references import Reference
from .spec_keys import check_keys, spec_delay, spec_number


class Controller(Protocol):
    """What the closed loop needs of a controller."""

    def reset(self) -> None: ...

    def step(self, x_meas: float, k: int) -> float: ...


def _add(a: np.ndarray | None, b: np.ndarray | None) -> np.ndarray | None:
    if a is None or b is None:
        return a if b is None else b
    n = max(len(a), len(b))
    return np.pad(a, (0, n - len(a))) + np.pad(b, (0, n - len(b)))


def _feedforward_u(spec: Mapping[str, Any], ref: Reference) -> np.ndarray | None:
    ff = spec.get("feedforward")
    if ff is None:
        return None
    if not isinstance(ff, Mapping) or set(ff) != {"options", "parameters"}:
        raise ValueError(
            "controller (state_space): feedforward must be null or an object with "
            "'options' and 'parameters'"
        )
    names = {f.name for f in fields(FeedforwardOptions)}
    bad = set(ff["options"]) - names
    if bad:
        raise ValueError(
            f"controller (state_space): feedforward.options: unknown key(s) "
            f"{sorted(bad)}; allowed {sorted(names)}"
        )
    opts = FeedforwardOptions(**ff["options"])
    return feedforward(ref.x, ref.Ts, ff["parameters"], opts, v_ref=ref.v, a_ref=ref.a).u


class DelayedController:
    """A controller with one sample of computation delay: the sample at t_k (its
    reference, its feedforward) runs on the measurement of t_k-1 (the first on its own), so
    what it computed from x_k is applied over [t_k+1, t_k+2)."""

    def __init__(self, inner: Controller) -> None:
        self.inner = inner
        self._prev: float | None = None

    def reset(self) -> None:
        """Reset the controller and forget the held measurement."""
        self.inner.reset()
        self._prev = None

    def step(self, x_meas: float, k: int) -> float:
        """u [V] of sample k from the measurement of sample k - 1."""
        y = x_meas if self._prev is None else self._prev
        self._prev = x_meas
        return self.inner.step(y, k)


SS_KEYS = {
    "design",
    "mech_hz",
    "mech_zeta",
    "mech_real_hz",
    "observer_hz",
    "observer_zeta",
    "observer_current_poles",
    "prefilter",
    "feedforward",
}


def build_state_space(
    spec: Mapping[str, Any], ref: Reference, u_ff: np.ndarray | None
) -> StateSpaceController:
    """The ``state_space`` controller: state feedback, integral action and current estimator
    designed on the spec's design model (with its computation delay)."""
    check_keys(spec, SS_KEYS)
    design = spec.get("design", {})
    if not isinstance(design, Mapping) or set(design) - set(DESIGN_KEYS):
        raise ValueError(
            f"controller (state_space): design must be an object with keys of {list(DESIGN_KEYS)}"
        )
    p = dict(paper_parameters())
    p.update(design)
    model = design_model(p, delay=spec_delay(spec))
    poles = default_poles(
        model,
        f_hz=spec_number(spec, "mech_hz", DEFAULT_MECH_HZ),
        zeta=spec_number(spec, "mech_zeta", DEFAULT_MECH_ZETA),
        f_real_hz=spec_number(spec, "mech_real_hz", DEFAULT_MECH_REAL_HZ),
    )
    cur = spec.get("observer_current_poles", DEFAULT_OBS_CURRENT)
    obs = default_observer_poles(
        model,
        f_hz=spec_number(spec, "observer_hz", DEFAULT_OBS_HZ),
        zeta=spec_number(spec, "observer_zeta", DEFAULT_OBS_ZETA),
        current_poles=(float(cur[0]), float(cur[1])),
    )
    return StateSpaceController(
        model,
        ref.x,
        poles=poles,
        observer_poles=obs,
        u_ff=_add(_feedforward_u(spec, ref), u_ff),
        prefilter=spec.get("prefilter", "zpetc"),
    )


#: the keys of a ``pid`` spec: the fields of PIDSettings
PID_KEYS = {f.name for f in fields(PIDSettings)}
#: the keys a ``pid`` spec must give (the others default as in PIDSettings)
PID_REQUIRED = ("Kp", "Kv", "Ki", "force_per_volt")


def _pid_kwargs(spec: Mapping[str, Any]) -> dict[str, Any]:
    """The PID's settings from ``spec``, in the order of PIDSettings (the first missing
    required key is the one named)."""
    kw: dict[str, Any] = {}
    for f in fields(PIDSettings):
        if f.name == "anti_windup":
            kw[f.name] = bool(spec.get(f.name, f.default))
        else:
            kw[f.name] = spec_number(spec, f.name, None if f.name in PID_REQUIRED else f.default)
    return kw


def build_pid(spec: Mapping[str, Any], ref: Reference, u_ff: np.ndarray | None) -> PID:
    """The force-equivalent ``pid`` controller."""
    check_keys(spec, PID_KEYS)
    return PID(ref.x, Ts=ref.Ts, u_ff=u_ff, **_pid_kwargs(spec))


def build_pid_lead(spec: Mapping[str, Any], ref: Reference, u_ff: np.ndarray | None) -> PID:
    """The ``pid_lead`` controller: the PID with a lead filter on its force command."""
    check_keys(spec, PID_KEYS | {"lead_zero_hz", "lead_pole_hz"})
    lead = (spec_number(spec, "lead_zero_hz"), spec_number(spec, "lead_pole_hz"))
    return PID(ref.x, Ts=ref.Ts, u_ff=u_ff, lead=lead, **_pid_kwargs(spec))


def build_lti(spec: Mapping[str, Any], ref: Reference, u_ff: np.ndarray | None) -> LTIController:
    """The ``lti`` controller of :func:`~.lti_realisation.lti_realisation`, run at the loop's
    sample time."""
    r = lti_realisation(spec)
    if abs(r.Ts - ref.Ts) > 1e-9 * ref.Ts:
        raise ValueError(
            f"controller (lti): Ts = {r.Ts!r} s is not the sample time of the loop, {ref.Ts!r} s"
        )
    return LTIController(
        ref.x, r.A, r.B, r.C, r.D, r.u_limit, L=r.L, s0=r.s0, s0_r=r.s0_r, u_ff=u_ff
    )
