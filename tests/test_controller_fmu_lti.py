"""The controller FMU's general linear controller (``ctrl.type`` 4, parameters ``lti.*``)
against the harness's Python ``lti`` controller: with recorded inputs the same u to 1e-12 V
(the C does the Python's operations in its order), the closed loop as controller FMU + plant
FMU the harness's run within 1e-9 m (unsaturated and with the clamp and the back-calculation
acting), the order and the values checked, an unstable controller ending with an error that
names the state."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pytest

from feeddrive.fmu import FMUError, Plant
from feeddrive.harness import (
    cascade_lti_spec,
    lti_spec,
    make_controller,
    pid_lti_spec,
    simulate_closed_loop,
    sinusoid,
)
from feeddrive.harness.controller_fmu import (
    ControllerFMU,
    controller_fmu_parameters,
    sinusoid_source,
)
from feeddrive.harness.two_fmus import simulate_two_fmus
from feeddrive.paper import paper_parameters

SINE = (0.005, 0.4, 0.15, 1.0)  # amplitude, period, centre, duration: 5 reversals
TOL_V = 1e-12
TOL_X = 1e-9


def _modal(n: int) -> dict[str, Any]:
    """An order-n controller given by its matrices: the PID-lead's realisation in another
    basis (a random similarity transform) with n - 3 extra stable, weakly coupled states."""
    base = pid_lti_spec(tf=2e-4, lead=(40.0, 120.0))
    from feeddrive.harness.controllers import lti_realisation

    r = lti_realisation(base)
    rng = np.random.default_rng(n)
    k = n - r.n
    A = np.zeros((n, n))
    A[: r.n, : r.n] = r.A
    A[r.n :, r.n :] = np.diag(rng.uniform(0.2, 0.8, k))
    B = np.vstack([r.B, 1e-3 * rng.standard_normal((k, 2))])
    C = np.hstack([r.C, 1e-3 * rng.standard_normal((1, k))])
    T = np.eye(n) + 0.1 * rng.standard_normal((n, n))
    Ti = np.linalg.inv(T)
    return lti_spec(
        5e-4, A=T @ A @ Ti, B=T @ B, C=C @ Ti, D=r.D, anti_windup={"pole": 0.4}, x0="rest"
    )


CASES: dict[str, Mapping[str, Any]] = {
    "pid_lead_tf": pid_lti_spec(tf=2e-4, lead=(40.0, 120.0)),
    "cascade": cascade_lti_spec(40.0, 30.0, 0.04, 600.0),
    "order_8": _modal(8),
    # the clamp hit on every reversal, the back-calculation acting
    "cascade_clamped": cascade_lti_spec(
        40.0, 30.0, 0.04, 600.0, u_limit=0.4, anti_windup={"pole": 0.5}
    ),
    "pid_clamped_no_antiwindup": pid_lti_spec(tf=2e-4, u_limit=0.4),
}


def _harness(spec: Mapping[str, Any]):
    ref = sinusoid(*SINE)
    with Plant(paper_parameters(), interface="cs") as plant:
        res = simulate_closed_loop(plant, make_controller(spec, ref), ref.n, float(ref.x[0]))
    return ref, res


@pytest.mark.parametrize("case", CASES)
def test_recorded_inputs_same_u(ctrl_fmu_built, case: str) -> None:
    spec = CASES[case]
    ref, res = _harness(spec)
    x_meas, u_py = np.asarray(res["x_meas"]), np.asarray(res["u"])
    values = controller_fmu_parameters(spec, reference=sinusoid_source(*SINE))
    with ControllerFMU(values) as c:
        c.start({"x_meas": float(x_meas[0])})
        u = np.array([c.step(k, float(x_meas[k])) for k in range(ref.n)])
    du = float(np.max(np.abs(u - u_py[: ref.n])))
    print(f"{case}: max |u_fmu - u_python| = {du:.3g} V, |u| up to {np.max(np.abs(u)):.3g} V")
    assert du <= TOL_V
    if "clamped" in case:
        assert np.mean(np.abs(u) == spec["u_limit"]) > 0.05  # the clamp did act


@pytest.mark.parametrize("case", ["pid_lead_tf", "order_8", "cascade_clamped"])
def test_closed_loop_two_fmus_agree_with_harness(ctrl_fmu_built, case: str) -> None:
    """Controller FMU + plant FMU (macro step Ts) against plant FMU + Python lti controller."""
    spec = CASES[case]
    ref, res = _harness(spec)
    values = controller_fmu_parameters(spec, reference=sinusoid_source(*SINE), quantum=1e-7)
    two = simulate_two_fmus(paper_parameters(), values, ref.n, float(ref.x[0]))
    dx = float(np.max(np.abs(two["x"] - res["x"])))
    print(f"{case}: max |x_two_fmus - x_harness| = {dx:.3g} m")
    assert dx <= TOL_X
    if "clamped" in case:  # the clamp held it back
        assert np.mean(np.abs(two["u"]) == spec["u_limit"]) > 0.05
    else:  # it did track the sinusoid
        assert np.ptp(res["x"]) > 0.9 * np.ptp(ref.x)


@pytest.mark.parametrize(
    "values, name, rule",
    [
        ({"ctrl.type": 4, "lti.n": 9}, "lti.n", "8]"),
        ({"ctrl.type": 4, "lti.n": -1}, "lti.n", "[0, "),
        ({"ctrl.type": 5}, "ctrl.type", "4]"),
        ({"ctrl.type": 4, "lti.A[8,8]": float("nan")}, "lti.A[8,8]", "finite"),
        ({"ctrl.type": 4, "lti.B[3,2]": 1e16}, "lti.B[3,2]", "1000000000000000]"),
        ({"ctrl.type": 4, "lti.L[1]": float("-inf")}, "lti.L[1]", "finite"),
    ],
)
def test_bad_lti_parameters_refused(ctrl_fmu_built, values, name: str, rule: str) -> None:
    with ControllerFMU({}) as c, pytest.raises(FMUError) as err:
        c.start(values)
    msg = str(err.value)
    assert name in msg and rule in msg, msg


def test_unstable_lti_ends_with_an_error_naming_the_state(ctrl_fmu_built) -> None:
    """A = 1.5 I (two states) fed by x_meas: the states grow until one overflows; every u
    answered before is finite (clamped), then the error names the linear controller's state."""
    values = {
        "ctrl.type": 4,
        "lti.n": 2,
        "lti.A[1,1]": 1.5,
        "lti.A[2,2]": 1.5,
        "lti.B[1,2]": 1.0,
        "lti.B[2,2]": 2.0,
        "lti.C[1]": 1.0,
        "lti.C[2]": -1.0,
    }
    us: list[float] = []
    with ControllerFMU(values) as c:
        c.start({"x_meas": 0.15})
        with pytest.raises(FMUError) as err:
            for k in range(5000):
                us.append(c.step(k, 0.15))
    assert 1700 < len(us) < 1800 and np.isfinite(us).all()
    msg = str(err.value)
    assert "linear controller's state lti.s[" in msg and "is not finite" in msg, msg


@pytest.fixture(scope="module")
def ctrl_fmu_built(fmu_path):
    from feeddrive.harness.controller_fmu import controller_fmu_path

    return controller_fmu_path()
