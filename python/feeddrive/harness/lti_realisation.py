"""The realisation of an ``lti`` spec: its matrices (given as such or as transfer
functions), clamp, back-calculation gain and first state, each key checked."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..control.lti import LTI_MAX_ORDER, back_calculation_gain, rest_state, tf_to_ss
from ..control.pid import DEFAULT_U_LIMIT
from .spec_keys import check_keys, spec_number

LTI_KEYS = {"Ts", "A", "B", "C", "D", "num", "den", "u_limit", "anti_windup", "x0"}


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
    check_keys(spec, LTI_KEYS)
    Ts = spec_number(spec, "Ts")
    if not Ts > 0:
        raise ValueError(f"controller (lti): Ts = {Ts!r} must be > 0 [s]")
    u_limit = spec_number(spec, "u_limit", DEFAULT_U_LIMIT)
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
        pole = spec_number(aw, "pole")
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
