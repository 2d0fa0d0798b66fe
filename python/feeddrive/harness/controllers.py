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
from dataclasses import asdict, dataclass, fields
from typing import Any, Protocol

import numpy as np

from ..control.design_model import design_model
from ..control.feedforward import FeedforwardOptions, feedforward
from ..control.lti import (
    LTI_MAX_ORDER,
    LTIController,
    back_calculation_gain,
    cascade_tf,
    pid_tf,
    rest_state,
    tf_to_ss,
)
from ..control.margins import Margins, poor_margins
from ..control.pid import DEFAULT_FORCE_PER_VOLT, DEFAULT_GAINS, DEFAULT_U_LIMIT, PID
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
from .references import Reference

#: The parameters the state-space design uses (kept in the spec's ``design``).
DESIGN_KEYS = (
    ("m", "Ts", "ripple.c[0]")
    + tuple(f"current.a[{j}]" for j in range(1, 6))
    + tuple(f"current.b[{j}]" for j in range(6))
)
#: Default lead of ``pid_lead`` [Hz]: with the default PID gains on the paper's design model
#: the phase margin goes from 28 to 47 deg (GM 7.3 dB, crossover 36 Hz, min|1+L| 0.50).
DEFAULT_LEAD = (40.0, 120.0)


class Controller(Protocol):
    """What the closed loop needs of a controller."""

    def reset(self) -> None: ...

    def step(self, x_meas: float, k: int) -> float: ...


def _json_value(v: Any) -> Any:
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    return float(v)


# ---------------------------------------------------------------- specs with defaults
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
    Kp: float = DEFAULT_GAINS["Kp"],
    Kv: float = DEFAULT_GAINS["Kv"],
    Ki: float = DEFAULT_GAINS["Ki"],
    force_per_volt: float = DEFAULT_FORCE_PER_VOLT,
    u_limit: float = DEFAULT_U_LIMIT,
    tf: float = 0.0,
    anti_windup: bool = False,
) -> dict[str, Any]:
    """Spec of the force-equivalent PID (defaults: :data:`feeddrive.control.pid.DEFAULT_GAINS`)."""
    return {
        "type": "pid",
        "Kp": float(Kp),
        "Kv": float(Kv),
        "Ki": float(Ki),
        "force_per_volt": float(force_per_volt),
        "u_limit": float(u_limit),
        "tf": float(tf),
        "anti_windup": bool(anti_windup),
    }


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
    (num, den); see the module docstring."""
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


# ---------------------------------------------------------------- spec -> controller
def _number(spec: Mapping[str, Any], key: str, default: Any = None) -> float:
    if key not in spec:
        if default is None:
            raise ValueError(f"controller ({spec.get('type')}): key {key!r} missing")
        return float(default)
    v = spec[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v):
        raise ValueError(f"controller ({spec.get('type')}): {key} = {v!r} is not a finite number")
    return float(v)


def _check_keys(spec: Mapping[str, Any], allowed: set[str]) -> None:
    unknown = set(spec) - allowed - {"type"} - COMMON_KEYS
    if unknown:
        raise ValueError(
            f"controller ({spec.get('type')}): unknown key(s) {sorted(unknown)}; "
            f"allowed {sorted(allowed)}"
        )


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


#: keys every type's spec may have: ``delay`` (0 or 1 sample of computation delay)
COMMON_KEYS = frozenset({"delay"})


def spec_delay(spec: Mapping[str, Any]) -> int:
    """The spec's computation delay [samples]: 0 (default) or 1; ValueError otherwise."""
    d = spec.get("delay", 0)
    if isinstance(d, bool) or d not in (0, 1):
        raise ValueError(f"controller ({spec.get('type')}): delay = {d!r}: allowed 0 or 1 sample")
    return int(d)


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


_SS_KEYS = {
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


def _state_space(
    spec: Mapping[str, Any], ref: Reference, u_ff: np.ndarray | None
) -> StateSpaceController:
    _check_keys(spec, _SS_KEYS)
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
        f_hz=_number(spec, "mech_hz", DEFAULT_MECH_HZ),
        zeta=_number(spec, "mech_zeta", DEFAULT_MECH_ZETA),
        f_real_hz=_number(spec, "mech_real_hz", DEFAULT_MECH_REAL_HZ),
    )
    cur = spec.get("observer_current_poles", DEFAULT_OBS_CURRENT)
    obs = default_observer_poles(
        model,
        f_hz=_number(spec, "observer_hz", DEFAULT_OBS_HZ),
        zeta=_number(spec, "observer_zeta", DEFAULT_OBS_ZETA),
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


_PID_KEYS = {"Kp", "Kv", "Ki", "force_per_volt", "u_limit", "tf", "anti_windup"}


def _pid_kwargs(spec: Mapping[str, Any]) -> dict[str, Any]:
    return {
        "Kp": _number(spec, "Kp"),
        "Kv": _number(spec, "Kv"),
        "Ki": _number(spec, "Ki"),
        "force_per_volt": _number(spec, "force_per_volt"),
        "u_limit": _number(spec, "u_limit", DEFAULT_U_LIMIT),
        "tf": _number(spec, "tf", 0.0),
        "anti_windup": bool(spec.get("anti_windup", False)),
    }


def _pid(spec: Mapping[str, Any], ref: Reference, u_ff: np.ndarray | None) -> PID:
    _check_keys(spec, _PID_KEYS)
    return PID(ref.x, Ts=ref.Ts, u_ff=u_ff, **_pid_kwargs(spec))


def _pid_lead(spec: Mapping[str, Any], ref: Reference, u_ff: np.ndarray | None) -> PID:
    _check_keys(spec, _PID_KEYS | {"lead_zero_hz", "lead_pole_hz"})
    lead = (_number(spec, "lead_zero_hz"), _number(spec, "lead_pole_hz"))
    return PID(ref.x, Ts=ref.Ts, u_ff=u_ff, lead=lead, **_pid_kwargs(spec))


_LTI_KEYS = {"Ts", "A", "B", "C", "D", "num", "den", "u_limit", "anti_windup", "x0"}


@dataclass(frozen=True)
class LTIRealisation:
    """What an ``lti`` spec describes: the matrices, the clamp, the back-calculation gain L
    and the first state s0 + s0_r x_ref[0]."""

    Ts: float
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    u_limit: float
    L: np.ndarray
    s0: np.ndarray
    s0_r: np.ndarray

    @property
    def n(self) -> int:
        return self.A.shape[0]


def _matrix(spec: Mapping[str, Any], key: str, shape: tuple[int, ...]) -> np.ndarray:
    try:
        m = np.asarray(spec[key], dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"controller (lti): {key} must be a matrix of numbers") from None
    if m.size == 0 and 0 in shape:
        return m.reshape(shape)
    if m.shape != shape:
        raise ValueError(f"controller (lti): {key} has shape {m.shape}, needs {shape}")
    if not np.all(np.isfinite(m)):
        raise ValueError(f"controller (lti): {key} has a value that is not finite")
    return m


def lti_realisation(spec: Mapping[str, Any]) -> LTIRealisation:
    """The realisation of an ``lti`` spec; ValueError naming the key for a bad one."""
    _check_keys(spec, _LTI_KEYS)
    Ts = _number(spec, "Ts")
    if not Ts > 0:
        raise ValueError(f"controller (lti): Ts = {Ts!r} must be > 0 [s]")
    u_limit = _number(spec, "u_limit", DEFAULT_U_LIMIT)
    if not u_limit > 0:
        raise ValueError(f"controller (lti): u_limit = {u_limit!r} must be > 0 [V]")
    ss, tf = (
        [k for k in ("A", "B", "C", "D") if k in spec],
        [k for k in ("num", "den") if k in spec],
    )
    if (ss and tf) or not (len(ss) == 4 or len(tf) == 2):
        raise ValueError(
            "controller (lti): give either A, B, C, D (state space) or num and "
            f"den (transfer functions), got {sorted(ss + tf)}"
        )
    if tf:
        try:
            A, B, C, D = tf_to_ss(spec["num"], spec["den"])
        except (TypeError, ValueError) as e:
            raise ValueError(f"controller (lti): {str(e).removeprefix('lti: ')}") from None
    else:
        try:
            n = len(spec["A"])
        except TypeError:
            raise ValueError(
                "controller (lti): A must be a square matrix (a list of rows)"
            ) from None
        A, B = _matrix(spec, "A", (n, n)), _matrix(spec, "B", (n, 2))
        C, D = _matrix(spec, "C", (1, n)), _matrix(spec, "D", (1, 2))
    n = A.shape[0]
    if n > LTI_MAX_ORDER:
        raise ValueError(f"controller (lti): order {n}; at most {LTI_MAX_ORDER} states")
    aw = spec.get("anti_windup")
    if aw is None:
        L = np.zeros(n)
    elif isinstance(aw, Mapping) and set(aw) == {"gain"}:
        L = _matrix({"anti_windup.gain": aw["gain"]}, "anti_windup.gain", (n,))
    elif isinstance(aw, Mapping) and set(aw) == {"pole"}:
        pole = _number(aw, "pole")
        try:
            L = back_calculation_gain(A, C, pole)
        except ValueError as e:
            raise ValueError(f"controller (lti): {str(e).removeprefix('lti: ')}") from None
    else:
        raise ValueError(
            f"controller (lti): anti_windup = {aw!r}: allowed null, "
            '{"gain": [n numbers]} or {"pole": p}'
        )
    x0 = spec.get("x0", "rest")
    s0, s0_r = np.zeros(n), np.zeros(n)
    if isinstance(x0, str):
        if x0 == "rest":
            s0_r = rest_state(A, B, C, D)
        elif x0 != "zero":
            raise ValueError(
                f"controller (lti): x0 = {x0!r}: allowed 'rest', 'zero' or a list of {n} numbers"
            )
    else:
        s0 = _matrix({"x0": x0}, "x0", (n,))
    return LTIRealisation(Ts=Ts, A=A, B=B, C=C, D=D, u_limit=u_limit, L=L, s0=s0, s0_r=s0_r)


def _lti(spec: Mapping[str, Any], ref: Reference, u_ff: np.ndarray | None) -> LTIController:
    r = lti_realisation(spec)
    if abs(r.Ts - ref.Ts) > 1e-9 * ref.Ts:
        raise ValueError(
            f"controller (lti): Ts = {r.Ts!r} s is not the sample time of the loop, {ref.Ts!r} s"
        )
    return LTIController(
        ref.x, r.A, r.B, r.C, r.D, r.u_limit, L=r.L, s0=r.s0, s0_r=r.s0_r, u_ff=u_ff
    )


# ---------------------------------------------------------------- controller -> spec
def _pid_spec_of(c: PID) -> dict[str, Any]:
    kw: dict[str, Any] = {
        "Kp": c.Kp,
        "Kv": c.Kv,
        "Ki": c.Ki,
        "force_per_volt": c.force_per_volt,
        "u_limit": c.u_limit,
        "tf": c.tf,
        "anti_windup": c.anti_windup,
    }
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
        "state_space", _state_space, state_space_spec, frozenset(_SS_KEYS) | COMMON_KEYS
    ),
    "pid": ControllerType("pid", _pid, pid_spec, frozenset(_PID_KEYS) | COMMON_KEYS),
    "pid_lead": ControllerType(
        "pid_lead",
        _pid_lead,
        pid_lead_spec,
        frozenset(_PID_KEYS | {"lead_zero_hz", "lead_pole_hz"}) | COMMON_KEYS,
    ),
    "lti": ControllerType("lti", _lti, pid_lti_spec, frozenset(_LTI_KEYS) | COMMON_KEYS),
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
