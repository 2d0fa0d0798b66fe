"""Controller specs with defaults: the JSON-able spec of each registry type
(:mod:`.controllers`) built from its design parameters or gains."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict
from typing import Any

import numpy as np

from ..control.feedforward import FeedforwardOptions
from ..control.lti import cascade_tf, pid_tf
from ..control.pid import DEFAULT_FORCE_PER_VOLT, DEFAULT_GAINS, DEFAULT_U_LIMIT, PIDSettings
from ..control.state_space import (
    DEFAULT_MECH_HZ,
    DEFAULT_MECH_REAL_HZ,
    DEFAULT_MECH_ZETA,
    DEFAULT_OBS_CURRENT,
    DEFAULT_OBS_HZ,
    DEFAULT_OBS_ZETA,
)
from ..paper import paper_parameters

#: The parameters the state-space design uses (kept in the spec's ``design``).
DESIGN_KEYS = (
    ("m", "Ts", "ripple.c[0]")
    + tuple(f"current.a[{j}]" for j in range(1, 6))
    + tuple(f"current.b[{j}]" for j in range(6))
)
#: Default lead of ``pid_lead`` [Hz]: with the default PID gains on the paper's design model
#: the phase margin goes from 28 to 47 deg (GM 7.3 dB, crossover 36 Hz, min|1+L| 0.50).
DEFAULT_LEAD = (40.0, 120.0)


def _json_value(v: Any) -> Any:
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    return float(v)


def state_space_spec(
    design_params: Mapping[str, Any] | None = None,
    prefilter: str | None = "zpetc",
    feedforward: FeedforwardOptions | None = None,
) -> dict[str, Any]:
    """Spec of the default state-space controller designed on ``design_params`` (over the
    paper's); with ``feedforward`` the feedforward runs on the same parameters."""
    p = dict(paper_parameters())
    p.update(design_params or {})
    ff = (
        None
        if feedforward is None
        else {
            "options": asdict(feedforward),
            "parameters": {k: _json_value(v) for k, v in p.items()},
        }
    )
    return {
        "type": "state_space",
        "design": {k: float(p[k]) for k in DESIGN_KEYS},
        "mech_hz": DEFAULT_MECH_HZ,
        "mech_zeta": DEFAULT_MECH_ZETA,
        "mech_real_hz": DEFAULT_MECH_REAL_HZ,
        "observer_hz": DEFAULT_OBS_HZ,
        "observer_zeta": DEFAULT_OBS_ZETA,
        "observer_current_poles": list(DEFAULT_OBS_CURRENT),
        "prefilter": prefilter,
        "feedforward": ff,
    }


def pid_spec(
    Kp: float = PIDSettings.Kp,
    Kv: float = PIDSettings.Kv,
    Ki: float = PIDSettings.Ki,
    force_per_volt: float = PIDSettings.force_per_volt,
    u_limit: float = PIDSettings.u_limit,
    tf: float = PIDSettings.tf,
    anti_windup: bool = PIDSettings.anti_windup,
) -> dict[str, Any]:
    """Spec of the force-equivalent PID (defaults: :class:`feeddrive.control.pid.PIDSettings`)."""
    s = PIDSettings(
        float(Kp),
        float(Kv),
        float(Ki),
        float(force_per_volt),
        float(u_limit),
        float(tf),
        bool(anti_windup),
    )
    return {"type": "pid", **asdict(s)}


def pid_lead_spec(
    lead_zero_hz: float = DEFAULT_LEAD[0], lead_pole_hz: float = DEFAULT_LEAD[1], **pid: Any
) -> dict[str, Any]:
    """Spec of the PID with a lead filter (``pid`` as for :func:`pid_spec`)."""
    spec = pid_spec(**pid)
    spec.update(
        {
            "type": "pid_lead",
            "lead_zero_hz": float(lead_zero_hz),
            "lead_pole_hz": float(lead_pole_hz),
        }
    )
    return spec


def lti_spec(
    Ts: float,
    A: Any = None,
    B: Any = None,
    C: Any = None,
    D: Any = None,
    num: Any = None,
    den: Any = None,
    u_limit: float = DEFAULT_U_LIMIT,
    anti_windup: Mapping[str, Any] | None = None,
    x0: Any = "rest",
) -> dict[str, Any]:
    """Spec of a general linear controller: state space (A, B, C, D) or transfer functions
    (num, den); see :mod:`.controllers`."""
    spec: dict[str, Any] = {"type": "lti", "Ts": float(Ts)}
    if num is not None or den is not None:
        spec["num"] = [np.asarray(p, float).tolist() for p in num]
        spec["den"] = (
            np.asarray(den, float).tolist()
            if np.ndim(den[0]) == 0
            else [np.asarray(p, float).tolist() for p in den]
        )
    else:
        for key, v in (("A", A), ("B", B), ("C", C), ("D", D)):
            spec[key] = np.asarray(v, float).tolist()
    spec.update(
        {
            "u_limit": float(u_limit),
            "anti_windup": None if anti_windup is None else dict(anti_windup),
            "x0": x0 if isinstance(x0, str) else np.asarray(x0, float).tolist(),
        }
    )
    return spec


def pid_lti_spec(
    Ts: float = 5e-4,
    Kp: float = DEFAULT_GAINS["Kp"],
    Kv: float = DEFAULT_GAINS["Kv"],
    Ki: float = DEFAULT_GAINS["Ki"],
    force_per_volt: float = DEFAULT_FORCE_PER_VOLT,
    tf: float = 0.0,
    lead: tuple[float, float] | None = None,
    u_limit: float = DEFAULT_U_LIMIT,
    anti_windup: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """The PID (filtered derivative ``tf``, optional ``lead``) of ``pid``/``pid_lead`` as an
    ``lti`` spec in transfer-function form (:func:`feeddrive.control.lti.pid_tf`)."""
    num, den = pid_tf(Kp, Kv, Ki, force_per_volt, Ts, tf=tf, lead=lead)
    return lti_spec(Ts, num=num, den=den, u_limit=u_limit, anti_windup=anti_windup)


def cascade_lti_spec(
    Kx: float,
    Kv: float,
    Ti: float,
    f_velocity: float,
    Ts: float = 5e-4,
    u_limit: float = DEFAULT_U_LIMIT,
    anti_windup: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """The cascaded P-PI with a velocity filter (:func:`feeddrive.control.lti.cascade_tf`)
    as an ``lti`` spec."""
    num, den = cascade_tf(Kx, Kv, Ti, f_velocity, Ts)
    return lti_spec(Ts, num=num, den=den, u_limit=u_limit, anti_windup=anti_windup)
