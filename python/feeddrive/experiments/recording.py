"""How a virtual experiment is recorded: an unrecorded settling hold, the closed loop run one
sample past the record, the sensors' effects, the sidecar meta; helpers shared by every
experiment (stroke limits, per-run seeds)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from ..data import Run
from ..harness.controllers import state_space_spec
from ..harness.references import Reference
from ..harness.runs import run_closed_loop, to_run
from ..harness.sensors import Sensors
from ..harness.sidecar import build_sidecar

#: Distance kept from the stroke ends [m] (the start-up sag under load must stay inside).
STROKE_MARGIN: float = 5e-3
#: Unrecorded hold before a closed-loop run's reference starts [s] (the loop settles).
HOLD: float = 0.5


def stroke(params: Mapping[str, Any]) -> tuple[float, float]:
    """The stroke [x_min, x_max] [m] of an FMU parameter set (default 0 ... 0.3 m)."""
    return float(params.get("stroke.x_min", 0.0)), float(params.get("stroke.x_max", 0.3))


def run_seed(seed: int, *keys: int | str) -> int:
    """A reproducible 32-bit seed for one run, derived from an experiment's seed and keys."""
    ints = [int(seed)] + [
        k if isinstance(k, int) else int.from_bytes(k.encode(), "little") for k in keys
    ]
    return int(np.random.SeedSequence(ints).generate_state(1)[0])


def closed_loop_measurement(
    params: Mapping[str, Any],
    sensors: Sensors,
    ref: Reference,
    meta: Mapping[str, Any],
    spec: Mapping[str, Any] | None = None,
    F_load: float = 0.0,
    u_ff: np.ndarray | None = None,
    hold: float = HOLD,
) -> Run:
    """One virtual closed-loop measurement as a recording.

    The drive first holds ``ref.x[0]`` (with the load hung) for ``hold`` seconds, which is
    simulated but not recorded, as on a real machine where the recording starts on a settled
    stage: the start-up sag under load or cogging is not in the run.  Time starts at 0 at
    the first recorded sample (``meta['hold_before_record']`` says how long the hold was).
    The loop runs one sample past the record so that the current is sampled as a DAQ
    samples it (:func:`sampled_signals`).

    Parameters
    ----------
    params : FMU parameters of the plant (SI).
    sensors : scale quantum, current noise (a real force on the stage, seen in i) and seed.
    ref : position reference sampled at the controller's Ts (what is recorded).
    meta : how the run was made (``name``, ``kind`` etc.): the sidecar's experiment-specific
        keys (:mod:`feeddrive.harness.sidecar`); ``experiment`` is ``meta['kind']``.
    spec : controller spec (default ``state_space_spec()``: the paper-designed controller).
    F_load : constant pulley load P [N], applied as F_ext = P and written as ``F_load``.
    u_ff : voltage added to the controller's output (e.g. an excitation), aligned with
        ``ref`` [V].
    hold : unrecorded settling time before ``ref`` starts [s] (>= 0).
    """
    if hold < 0:
        raise ValueError(f"closed_loop_measurement: hold {hold!r} must be >= 0")
    spec = dict(state_space_spec() if spec is None else spec)
    k0 = int(round(hold / ref.Ts))
    # hold, the recorded reference, and one sample more for the current (see sampled_signals)
    x_full = np.concatenate([np.full(k0, ref.x[0]), ref.x, ref.x[-1:]])
    v_full = np.concatenate([np.zeros(k0), ref.v, [0.0]])
    a_full = np.concatenate([np.zeros(k0), ref.a, [0.0]])
    full = Reference(ref.Ts, x_full, v_full, a_full)
    uff = None if u_ff is None else np.concatenate([np.zeros(k0), np.asarray(u_ff, float)])
    res = run_closed_loop(params, spec, full, u_ff=uff, sensors=sensors, F_ext=float(F_load))
    m = build_sidecar(
        str(meta.get("kind", "closed_loop")),
        ref.Ts,
        spec,
        sensors,
        F_load=float(F_load),
        hold_before_record=k0 * ref.Ts,
        **meta,
    )
    run = to_run(sampled_signals(res), sensors, x_ref=full.x[:-1], F_load=float(F_load), meta=m)
    cols: dict[str, Any] = {c: a[k0:] for c, a in run.columns().items()}
    cols["time"] = cols["time"] - cols["time"][0]
    return Run(**cols, meta=run.meta)


def sampled_signals(res: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """What a DAQ records at t_k, from a simulation that ran one sample beyond the run.

    ``simulate_*`` already give Eq. 2's i[k] (held over [t_k, t_k+1)) at row k; the last row's
    current is only a repeat of the one before (its sample lies beyond the simulation), so
    the run keeps rows 0..n-1 of time, u, x and i.
    """
    return {
        "time": np.asarray(res["time"])[:-1],
        "u": np.asarray(res["u"])[:-1],
        "x": np.asarray(res["x"])[:-1],
        "i": np.asarray(res["i"])[:-1],
    }
