"""The controller FMU (``DriveController.fmu``): a controller spec -> its parameter set, and
the FMU driven sample by sample.

The FMU (C, fmu_src/models/controller/) runs the harness's controllers -- ``state_space``, ``pid``,
``pid_lead``, ``lti`` -- with the ZPETC pre-filter and the feedforward.  The design stays in Python:
:func:`controller_fmu_parameters` designs the controller of a spec (pole placement, observer,
ZPETC, exactly as :func:`~.controllers.make_controller` does) and returns the FMU's start
values: the controller matrices ``ss.*`` (u = Cc s + Dy y + Dr r + u_ff, s <- Ac s + By y +
Br r + Bu (u - u_ff)), the pre-filter ``zpetc.*`` (b, a, lfilter_zi, preview), the PID gains
``pid.*`` and lead corners ``lead.*``, a linear controller's realisation ``lti.*`` (A, B,
C, D, back-calculation gain L, first state s0 + s0_r x_ref[0]), the feedforward switches ``ff.*`` and the nominal plant
``plant.*`` the feedforward runs on.  For another plant: put its parameters in the spec
(``state_space_spec(design_params=...)``, or a PID's gains) and call it again.

Reference: ``ref.source`` 0 reads the inputs ``x_ref``, ``v_ref``, ``a_ref``, *preview*
samples ahead (``zpetc.preview``: x_ref(t + preview Ts)), the samples before the first one
taken at rest at the first value; :func:`sinusoid_source` and :func:`point_to_point_source`
select the internal generators (the harness's :func:`~.references.sinusoid` and
:func:`~.references.point_to_point`; a circle's second axis is a sinusoid with phase).
Sample convention: ``u`` at t_k is the output for ``x_meas`` set at t_k (no extra delay), as
in :func:`~.simulate.simulate_closed_loop`.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import fields
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from scipy import signal

from ..control.feedforward import FeedforwardOptions
from ..control.pid import PID
from ..control.state_space import StateSpaceController
from ..fmu import FMUError, Plant
from ..model_description import FMUNotFoundError
from .controllers import DelayedController, lti_realisation, make_controller, spec_delay
from .references import Reference, sinusoid

CONTROLLER_FMU_ENV = "FEEDDRIVE_CONTROLLER_FMU"
DEFAULT_CONTROLLER_FMU = Path(str(resources.files("feeddrive") / "DriveController.fmu"))
NS_MAX = 8  #: state-space controller states the FMU holds
NZ_MAX = 16  #: ZPETC coefficients the FMU holds
TYPES = {"state_space": 1, "pid": 2, "pid_lead": 3, "lti": 4}
FRICTION = {"none": 0, "static": 1, "gms": 2}

Values = dict[str, float | int | bool]


def controller_fmu_path(path: str | Path | None = None) -> Path:
    """``path``, else ``$FEEDDRIVE_CONTROLLER_FMU``, else the package's copy (``make fmu``)."""
    p = (
        Path(path)
        if path is not None
        else Path(os.environ.get(CONTROLLER_FMU_ENV) or DEFAULT_CONTROLLER_FMU)
    )
    if not p.is_file():
        raise FMUNotFoundError(
            f"{p}: no controller FMU there (make fmu builds "
            f"build/DriveController.fmu; or set {CONTROLLER_FMU_ENV})"
        )
    return p


def sinusoid_source(
    amplitude: float, period: float, centre: float, duration: float, phase: float = 0.0
) -> Values:
    """Parameters of the internal sinusoid x = centre - amplitude cos(2 pi t/period + phase)
    (held after ``duration``); phase 0 is :func:`~.references.sinusoid`."""
    return {
        "ref.source": 1,
        "ref.amplitude": float(amplitude),
        "ref.period": float(period),
        "ref.centre": float(centre),
        "ref.duration": float(duration),
        "ref.phase": float(phase),
    }


def point_to_point_source(
    x_start: float, x_end: float, speed: float, accel: float, dwell: float = 0.2
) -> Values:
    """Parameters of the internal trapezoidal move (:func:`~.references.point_to_point`)."""
    return {
        "ref.source": 2,
        "ref.x_start": float(x_start),
        "ref.x_end": float(x_end),
        "ref.speed": float(speed),
        "ref.accel": float(accel),
        "ref.dwell": float(dwell),
    }


def _state_space_values(c: StateSpaceController) -> Values:
    lti = c.lti
    n = lti["Ac"].shape[0]
    if n > NS_MAX:
        raise ValueError(
            f"controller_fmu: the state-space controller has {n} states; the FMU "
            f"holds at most {NS_MAX}"
        )
    out: Values = {
        "ss.n": n,
        "ss.Dy": float(lti["Dy"]),
        "ss.Dr": float(lti["Dr"]),
        "u_limit": float(c.u_limits[1]),
    }
    if c.u_limits[0] != -c.u_limits[1]:
        raise ValueError(f"controller_fmu: u_limits {c.u_limits} must be symmetric")
    for key in ("By", "Br", "Bu", "Cc"):
        out.update({f"ss.{key}[{i + 1}]": float(lti[key][i]) for i in range(n)})
    out.update(
        {f"ss.Ac[{i + 1},{j + 1}]": float(lti["Ac"][i, j]) for i in range(n) for j in range(n)}
    )
    if c.zpetc is None:
        out["zpetc.on"] = False
        return out
    b, a = np.asarray(c.zpetc.b, float), np.asarray(c.zpetc.a, float)
    L = max(len(b), len(a))
    if L > NZ_MAX:
        raise ValueError(
            f"controller_fmu: the ZPETC filter has {L} coefficients; the FMU holds at most {NZ_MAX}"
        )
    b, a = np.pad(b, (0, L - len(b))), np.pad(a, (0, L - len(a)))
    zi = signal.lfilter_zi(c.zpetc.b, c.zpetc.a)
    out.update({"zpetc.on": True, "zpetc.preview": int(c.zpetc.preview), "zpetc.order": L - 1})
    out.update({f"zpetc.b[{j + 1}]": float(b[j]) for j in range(L)})
    out.update({f"zpetc.a[{j + 1}]": float(a[j]) for j in range(L)})
    out.update({f"zpetc.zi[{j + 1}]": float(zi[j]) for j in range(len(zi))})
    return out


def _pid_values(c: PID) -> Values:
    out: Values = {
        "pid.Kp": c.Kp,
        "pid.Kv": c.Kv,
        "pid.Ki": c.Ki,
        "pid.force_per_volt": c.force_per_volt,
        "pid.tf": c.tf,
        "pid.anti_windup": c.anti_windup,
        "u_limit": c.u_limit,
        "zpetc.on": False,
    }
    if c.lead is not None:
        out.update({"lead.zero_hz": c.lead[0], "lead.pole_hz": c.lead[1]})
    return out


def _lti_values(spec: Mapping[str, Any]) -> Values:
    """``lti.*`` of an ``lti`` spec: its realisation (A, B, C, D), the back-calculation gain
    and the first state, as :class:`~feeddrive.control.lti.LTIController` runs them."""
    r = lti_realisation(spec)
    n = r.n
    if n > NS_MAX:
        raise ValueError(
            f"controller_fmu: the lti controller has {n} states; the FMU holds at most {NS_MAX}"
        )
    out: Values = {
        "lti.n": n,
        "lti.D[1]": float(r.D[0, 0]),
        "lti.D[2]": float(r.D[0, 1]),
        "u_limit": r.u_limit,
        "zpetc.on": False,
        "ff.on": False,
    }
    for key, vec in (("C", r.C[0]), ("L", r.L), ("s0", r.s0), ("s0_r", r.s0_r)):
        out.update({f"lti.{key}[{i + 1}]": float(vec[i]) for i in range(n)})
    out.update({f"lti.B[{i + 1},{j + 1}]": float(r.B[i, j]) for i in range(n) for j in range(2)})
    out.update({f"lti.A[{i + 1},{j + 1}]": float(r.A[i, j]) for i in range(n) for j in range(n)})
    return out


def _feedforward_values(ff: Mapping[str, Any] | None) -> Values:
    if ff is None:
        return {"ff.on": False}
    names = {f.name for f in fields(FeedforwardOptions)}
    bad = set(ff["options"]) - names
    if bad:
        raise ValueError(f"controller_fmu: feedforward.options: unknown key(s) {sorted(bad)}")
    o = FeedforwardOptions(**ff["options"])
    if o.current_loop != "dc":
        raise ValueError(
            f"controller_fmu: feedforward current_loop = {o.current_loop!r}: the "
            f"FMU implements 'dc' only"
        )
    if o.friction not in FRICTION:
        raise ValueError(
            f"controller_fmu: feedforward friction = {o.friction!r}: allowed {sorted(FRICTION)}"
        )
    out: Values = {
        "ff.on": True,
        "ff.inertia": o.inertia,
        "ff.cogging": o.cogging,
        "ff.ripple": o.ripple,
        "ff.friction": FRICTION[o.friction],
        "ff.v_eps": float(o.v_eps),
        "ff.offset": o.offset,
    }
    out.update({f"plant.{k}": v for k, v in ff["parameters"].items()})
    return out


def controller_fmu_parameters(
    spec: Mapping[str, Any],
    Ts: float = 5e-4,
    reference: Mapping[str, Any] | None = None,
    quantum: float = 0.0,
    handover: int = 0,
) -> Values:
    """The controller FMU's start values for the controller ``spec`` (a sidecar ``controller``).

    Parameters
    ----------
    spec : ``state_space``, ``pid``, ``pid_lead`` or ``lti`` spec (see :mod:`.controllers`).
    Ts : sample time [s] (the state-space design takes it from ``spec["design"]``, an
        ``lti`` spec from its ``Ts``).
    reference : :func:`sinusoid_source` / :func:`point_to_point_source` values, or None for
        the inputs (``ref.source`` 0).
    quantum : scale resolution the FMU applies to ``x_meas`` [m] (0: none; the harness
        quantises before the controller).
    handover : samples of delay the master adds by itself: 0 for a Gauss-Seidel master (ours,
        plant first), 1 for a Jacobi engine at h = Ts (libcosim, Ecos, fmpy's SSP), whose
        one-step handover *is* one sample of computation delay.  The FMU's ``ctrl.delay`` is
        the spec's ``delay`` less ``handover`` (the design keeps the spec's delay).

    ValueError (from the registry, naming the key) for a bad spec, or when the FMU cannot hold
    the controller.
    """
    kind = spec.get("type") if isinstance(spec, Mapping) else None
    if kind not in TYPES:
        raise ValueError(f"controller_fmu: type {kind!r} is not known; known: {sorted(TYPES)}")
    if kind == "state_space":
        Ts = float(spec.get("design", {}).get("Ts", Ts))
    if kind == "lti":
        Ts = lti_realisation(spec).Ts
    ctrl = make_controller(spec, sinusoid(0.0, 1.0, 0.15, 10 * Ts, Ts=Ts))
    delay = spec_delay(spec) - int(handover)
    if handover not in (0, 1) or delay < 0:
        raise ValueError(
            f"controller_fmu: handover = {handover!r} with the spec's delay = "
            f"{spec_delay(spec)}: allowed handover 0 or 1, at most the delay"
        )
    if isinstance(ctrl, DelayedController):
        ctrl = ctrl.inner
    out: Values = {
        "Ts": Ts,
        "ctrl.type": TYPES[kind],
        "scale.quantum": float(quantum),
        "ref.source": 0,
    }
    if delay:
        out["ctrl.delay"] = delay
    if kind == "lti":
        out.update(_lti_values(spec))
    elif isinstance(ctrl, StateSpaceController):
        out.update(_state_space_values(ctrl))
        out.update(_feedforward_values(spec.get("feedforward")))
    elif isinstance(ctrl, PID):
        out.update(_pid_values(ctrl))
        out["ff.on"] = False
    else:
        raise ValueError(f"controller_fmu: the controller FMU has no form of {type(ctrl).__name__}")
    out.update(reference or {})
    return out


def preview_inputs(ref: Reference, preview: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x_ref, v_ref, a_ref inputs for ``ref.source`` 0: sample k carries the reference at
    k + ``preview`` (held at its end)."""
    idx = np.minimum(np.arange(len(ref.x)) + int(preview), len(ref.x) - 1)
    return ref.x[idx], ref.v[idx], ref.a[idx]


class ControllerFMU(Plant):
    """One instance of the controller FMU (co-simulation), driven sample by sample.

    ``start()`` initialises it with ``parameters``; ``step(k, x_meas, x_ref, v_ref, a_ref)``
    sets the inputs of sample k, reads u [V] and advances one Ts.
    """

    def __init__(
        self,
        parameters: Mapping[str, float | int | bool] | None = None,
        path: str | Path | None = None,
        log: bool = False,
    ) -> None:
        super().__init__(parameters, interface="cs", path=controller_fmu_path(path), log=log)
        self.Ts = float(self.parameters.get("Ts", 5e-4))

    def start(
        self,
        start_values: Mapping[str, float] | None = None,
        t0: float = 0.0,
        stop_time: float | None = None,
    ) -> None:
        """Instantiate and initialise (``start_values``: e.g. the first ``x_meas``)."""
        super().start(start_values, t0=t0, stop_time=stop_time)
        self._raw = self.raw_calls()
        self._inp = self.raw(["x_meas", "x_ref", "v_ref", "a_ref"])
        self._out = self.raw(["u"])
        self._t0 = t0

    def step(
        self, k: int, x_meas: float, x_ref: float = 0.0, v_ref: float = 0.0, a_ref: float = 0.0
    ) -> float:
        """u[k] for the inputs of sample k; then advance to sample k + 1."""
        self._inp.set((x_meas, x_ref, v_ref, a_ref))
        u = float(self._out.get()[0])
        r = self._raw
        if r.do_step(r.component, self._t0 + k * self.Ts, self.Ts, 1) > 1:
            raise FMUError(
                f"fmi2DoStep at sample {k}: " + (self.messages[-1] if self.messages else "")
            )
        return u
