"""The controller registry: a JSON-able spec (a run's sidecar ``controller``) <-> a controller.

Every controller has ``reset()`` and ``step(x_meas, k) -> u`` [V]; it is built for one
:class:`~feeddrive.harness.references.Reference`.  Types (``spec["type"]``):

``state_space``
    State feedback + integral action + current estimator designed on the design model of
    ``design`` (m, Ts, ripple.c[0], current.a/b), poles from ``mech_hz``, ``mech_zeta``,
    ``mech_real_hz``, observer from ``observer_hz``, ``observer_zeta``,
    ``observer_current_poles``; ``prefilter`` "zpetc" or null; ``feedforward`` null or
    {"options": FeedforwardOptions fields, "parameters": the nominal FMU parameters it runs on}.
``pid``
    Force-equivalent PID: ``Kp`` [N/m], ``Kv`` [N s/m], ``Ki`` [N/(m s)], ``force_per_volt``
    [N/V] (required), ``u_limit`` [V], ``tf`` [s], ``anti_windup`` (optional).
``pid_lead``
    The PID with a lead filter on its force command: also ``lead_zero_hz``, ``lead_pole_hz``.
``lti``
    Any linear digital controller from (x_ref, x_meas) [m] to u [V]
    (:mod:`feeddrive.control.lti`): ``Ts`` [s] (required, the run's sample time), either
    ``A`` (n x n), ``B`` (n x 2), ``C`` (1 x n), ``D`` (1 x 2) or ``num`` ([num for x_ref,
    num for x_meas], descending powers of z) with ``den`` (one list, or one per input);
    ``u_limit`` [V]; ``anti_windup`` null, ``{"gain": [L_1 .. L_n]}`` or ``{"pole": p}``
    (back-calculation, all eigenvalues of A - L C at p); ``x0`` "rest" (default), "zero" or
    a list of n states.  Order n <= :data:`~feeddrive.control.lti.LTI_MAX_ORDER`.

Every type also takes ``delay`` (0, the default, or 1 sample of computation delay): with 1,
the sample at t_k runs on the measurement of t_k-1 (:class:`DelayedController`), as a drive
that applies at t_k+1 what it computed from x_k; the state-space design then places its poles
on the design model with that delay (:func:`~feeddrive.control.design_model.design_model`),
and a spec whose delayed loop has poor margins (:func:`delay_margins`,
:func:`~feeddrive.control.margins.poor_margins`) is built with a :class:`PoorMarginsWarning`.

:func:`make_controller` builds one (ValueError naming the key for a bad spec);
:func:`controller_spec` gives the spec back from a controller.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from ..control.design_model import design_model
from ..control.margins import Margins, poor_margins
from ..control.pid import PID, PIDSettings
from ..control.state_space import StateSpaceController
from ..paper import paper_parameters
from .controller_builders import (
    PID_KEYS,
    SS_KEYS,
    Controller,
    DelayedController,
    build_lti,
    build_pid,
    build_pid_lead,
    build_state_space,
)
from .controller_specs import (
    DEFAULT_LEAD,
    DESIGN_KEYS,
    cascade_lti_spec,
    lti_spec,
    pid_lead_spec,
    pid_lti_spec,
    pid_spec,
    state_space_spec,
)
from .lti_realisation import LTI_KEYS, LTIRealisation, lti_realisation
from .references import Reference
from .spec_keys import COMMON_KEYS, spec_delay

__all__ = [
    "COMMON_KEYS",
    "CONTROLLERS",
    "DEFAULT_LEAD",
    "DESIGN_KEYS",
    "Controller",
    "ControllerType",
    "DelayedController",
    "LTIRealisation",
    "PoorMarginsWarning",
    "cascade_lti_spec",
    "controller_spec",
    "delay_margins",
    "lti_realisation",
    "lti_spec",
    "make_controller",
    "pid_lead_spec",
    "pid_lti_spec",
    "pid_spec",
    "spec_delay",
    "state_space_spec",
]


def _pid_spec_of(c: PID) -> dict[str, Any]:
    kw: dict[str, Any] = {f.name: getattr(c, f.name) for f in fields(PIDSettings)}
    return pid_spec(**kw) if c.lead is None else pid_lead_spec(*c.lead, **kw)


@dataclass(frozen=True)
class ControllerType:
    """One registry entry: how a spec becomes a controller."""

    name: str
    build: Callable[[Mapping[str, Any], Reference, np.ndarray | None], Controller]
    default_spec: Callable[[], dict[str, Any]]
    #: the keys a spec of this type may have besides ``type``
    keys: frozenset[str] = frozenset()


CONTROLLERS: dict[str, ControllerType] = {
    "state_space": ControllerType(
        "state_space", build_state_space, state_space_spec, frozenset(SS_KEYS) | COMMON_KEYS
    ),
    "pid": ControllerType("pid", build_pid, pid_spec, frozenset(PID_KEYS) | COMMON_KEYS),
    "pid_lead": ControllerType(
        "pid_lead",
        build_pid_lead,
        pid_lead_spec,
        frozenset(PID_KEYS | {"lead_zero_hz", "lead_pole_hz"}) | COMMON_KEYS,
    ),
    "lti": ControllerType("lti", build_lti, pid_lti_spec, frozenset(LTI_KEYS) | COMMON_KEYS),
}


class PoorMarginsWarning(UserWarning):
    """A controller spec whose loop, with its computation delay, has poor margins."""


def delay_margins(spec: Mapping[str, Any], ctrl: Controller) -> Margins | None:
    """The loop margins of ``ctrl`` (built from ``spec``) on the design model with the
    spec's computation delay: the state-space design's own model, the paper's for a PID (its
    ``force_per_volt`` is the paper's drive); None for an ``lti`` controller."""
    if isinstance(ctrl, DelayedController):
        ctrl = ctrl.inner
    if isinstance(ctrl, StateSpaceController):
        return ctrl.margins()
    if isinstance(ctrl, PID):
        return ctrl.margins(design_model(paper_parameters(), delay=spec_delay(spec)))
    return None


def _warn_poor_margins(spec: Mapping[str, Any], ctrl: Controller) -> None:
    m = delay_margins(spec, ctrl)
    poor = [] if m is None else poor_margins(m)
    if poor:
        warnings.warn(
            f"controller ({spec.get('type')}) with delay = {spec_delay(spec)}: " + "; ".join(poor),
            PoorMarginsWarning,
            stacklevel=3,
        )


def make_controller(
    spec: Mapping[str, Any], ref: Reference, u_ff: np.ndarray | None = None
) -> Controller:
    """The controller ``spec`` describes, for reference ``ref``.

    ``u_ff`` [V] per sample is added to the controller's output (an excitation, or a
    feedforward computed elsewhere), on top of a feedforward the spec itself names.  The
    controller keeps a copy of its spec as ``.spec``.  ValueError for an unknown type or a
    bad key (named).
    """
    if not isinstance(spec, Mapping):
        raise ValueError(f"controller: must be an object, got {type(spec).__name__}")
    kind = spec.get("type")
    if kind not in CONTROLLERS:
        raise ValueError(f"controller: type {kind!r} is not known; known: {sorted(CONTROLLERS)}")
    delay = spec_delay(spec)
    ctrl = CONTROLLERS[kind].build(spec, ref, None if u_ff is None else np.asarray(u_ff, float))
    if delay:
        _warn_poor_margins(spec, ctrl)
        ctrl = DelayedController(ctrl)
    ctrl.spec = dict(spec)  # type: ignore[attr-defined]  # every controller class takes it; the protocol has what the loop calls
    return ctrl


def controller_spec(ctrl: Controller) -> dict[str, Any]:
    """The JSON-able spec of a controller (the one it was made from, or a PID's own)."""
    if isinstance(ctrl, PID) and getattr(ctrl, "spec", {}).get("delay", 0) == 0:
        return _pid_spec_of(ctrl)
    spec = getattr(ctrl, "spec", None)
    if spec is None:
        raise ValueError(
            f"controller_spec: a {type(ctrl).__name__} not made by make_controller has no spec"
        )
    return dict(spec)
