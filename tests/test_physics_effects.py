"""One test per effect switch (EFFECTS.md, ``effects.*`` of modelDescription.xml): the Python
physics (feeddrive.physics, compiled once) and the FMU in the same state agree to 1e-9 N.

The state is set as the FMU's start values (x, v, friction.F[1..10], u, F_ext) and read back
after initialisation: K_f, F_cogging, i, F_motor, F_friction, m a and the element rates."""

from __future__ import annotations

import numpy as np
import pytest

from feeddrive.fmu import Plant
from feeddrive.paper import SWITCHABLE_EFFECTS, paper_parameters
from feeddrive.physics import (
    GMSParameters,
    applied_force,
    compile,
    element_forces,
    element_rates,
    karnopp_friction,
)

pytestmark = pytest.mark.usefixtures("fmu_path")  # on both FMI versions (conftest)

TOL = 1e-9  #: N (and N/A for K_f, A for i)
OUT = ("K_f", "F_cogging", "i", "F_motor", "F_friction", "a")
#: Parameters that make every switch visible: asymmetry and offset non-zero.
#: The friction-level profile (position_friction) rises over 0.05-0.25 m with a bump.
PROFILE = {
    "friction_profile.x_start": 0.05,
    "friction_profile.x_end": 0.25,
    "friction_profile.n": 6,
    **{f"friction_profile.c[{j + 1}]": c for j, c in enumerate([0.0, 0.1, 0.45, -0.2, 0.3, 0.25])},
}
BASE = dict(
    paper_parameters(),
    **{"offset.F": 1.7, "asymmetry.dF": 1.3, "asymmetry.dsigma2": 12.0},
    **PROFILE,
)


def states(prm: GMSParameters, v: float, slip: tuple[int, ...], x: float = 0.0) -> np.ndarray:
    """Element forces: half their limit (stuck) except ``slip`` (beyond it: they slip)."""
    S = float(prm.level(v, x)) if v != 0 else float(prm.break_away(1.0, x))
    F = 0.5 * np.asarray(prm.nu) * S * np.sign(v)
    for j in slip:
        F[j] = 1.3 * prm.nu[j] * S * np.sign(v)
    return F


def fmu_outputs(plant: Plant, start: dict) -> dict[str, float]:
    plant.start(start_values=start)
    names = list(OUT) + [f"der(friction.F[{j}])" for j in range(1, 11)]
    return plant.get(names)


def python_outputs(
    P, x: float, v: float, F: np.ndarray, slip: tuple[int, ...], u: float, F_ext: float
) -> dict[str, float]:
    """Eq. 1 in the given state from the compiled parameters."""
    K_f, F_cg = float(P.K_f(x)), float(P.F_cg(x))
    i = P.current.G1 * u  # the loop's history starts at the steady state of u
    F_motor = K_f * i
    F_app = float(applied_force(F_motor, F_cg, F_ext, P.F_offset))
    slipping = np.zeros(len(F), dtype=bool)
    slipping[list(slip)] = True
    if P.prerolling:
        d = int(np.sign(v)) if slip else 0
        Fe = element_forces(P.friction, v, F, slipping, d, x)
        F_f = float(np.sum(Fe) + P.friction.viscous(v))
        rates = element_rates(P.friction, v, F, slipping, d, x)
    else:
        F_f = float(
            karnopp_friction(
                np.array([v]),
                np.array([F_app]),
                P.friction,
                0.0 if v != 0 else 1e-300,
                np.array([x]),
            )[0][0]
        )
        rates = np.zeros(len(F))
    stuck_static = (
        not P.prerolling and v == 0 and abs(F_app) < float(P.friction.break_away(F_app, x))
    )
    return {
        "K_f": K_f,
        "F_cogging": F_cg,
        "i": i,
        "F_motor": F_motor,
        "F_friction": F_f,
        "ma": 0.0 if stuck_static else F_app - F_f,
        "rates": rates,
    }


CASES = [  # x [m], v [m/s], slipping elements, u [V], F_ext [N]
    (0.1234, 2e-3, (), 0.5, 0.0),
    (0.0871, -4e-3, (1,), -0.4, 2.5),
    (0.3312, 1e-2, (0, 3), 0.2, -1.0),  # outside the stroke: maps clamped
    (0.2001, 0.0, (), 0.25, 0.0),  # at rest
]


def check(effect: str, on: bool, fmu_path) -> None:
    params = dict(BASE, **{f"effects.{effect}": on})
    P = compile(params)
    with Plant(params, interface="me", path=fmu_path) as plant:
        for x, v, slip, u, F_ext in CASES:
            slip = slip if (P.prerolling and v != 0) else ()
            F = states(P.friction, v, slip, x)
            start = {"x": x, "v": v, "u": u, "F_ext": F_ext}
            start.update({f"friction.F[{j + 1}]": float(F[j]) for j in range(len(F))})
            got = fmu_outputs(plant, start)
            exp = python_outputs(P, x, v, F, slip, u, F_ext)
            for k in ("K_f", "F_cogging", "i", "F_motor", "F_friction"):
                assert got[k] == pytest.approx(exp[k], abs=TOL), (effect, on, x, v, k)
            assert P.m * got["a"] == pytest.approx(exp["ma"], abs=TOL), (effect, on, x, v)
            rates = [got[f"der(friction.F[{j + 1}])"] for j in range(len(F))]
            # rates of order k v ~ 1e4 N/s: relative 1e-12
            np.testing.assert_allclose(rates, exp["rates"], rtol=1e-12, atol=TOL)


@pytest.mark.parametrize("on", [True, False], ids=["on", "off"])
@pytest.mark.parametrize("effect", SWITCHABLE_EFFECTS)
def test_effect_switch_python_equals_fmu(effect: str, on: bool, fmu_path) -> None:
    check(effect, on, fmu_path)


def test_current_loop_samples_python_equals_fmu(fmu_path) -> None:
    """current_dynamics on: i after each sample equals G(z) u filtered from the steady state.

    Co-simulation: initialisation takes the sample at t = 0 (history at the steady state of
    u[0]); the sample at t_k = k Ts falls on the end of step k and is taken at the start of
    step k + 1 with the input set before it, u[k + 1]; so u[1] is never sampled."""
    P = compile(BASE)
    u = 0.3 * np.sin(np.arange(40) * 0.7) + 0.1
    with Plant(BASE, interface="cs", path=fmu_path) as plant:
        plant.start(start_values={"u": float(u[0])})
        got = []
        for k in range(1, len(u)):
            plant.set({"u": float(u[k])})
            plant.do_step((k - 1) * P.Ts, P.Ts)
            got.append(plant.get(["i"])["i"])
    n0 = 2000  # long enough at u[0] for the steady state (poles < 0.8)
    i = P.current.current(np.concatenate((np.full(n0, u[0]), u[2:])))[n0:]
    assert got[0] == pytest.approx(P.current.G1 * u[0], abs=1e-12)
    np.testing.assert_allclose(got[1:], i, rtol=0, atol=1e-12)
