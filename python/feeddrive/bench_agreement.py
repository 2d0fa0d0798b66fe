"""`make bench`'s agreement rows on the 6 s, 30 mm closed-loop sinusoid (the loop of
:func:`feeddrive.bench.python_rows`, state-space controller, 100 nm scale):

- Python vs FMU: the package's twin of the physics (:mod:`feeddrive.physics`) in the plant
  FMU's state at every sample (cogging, force constant with ripple, friction, Eq. 1, the current
  loop of Eq. 2), the twin's GMS integrated along the FMU's motion, and the package's own
  closed loop (:func:`feeddrive.control.simulate_linear`: the design model with the GMS and
  the cogging as its force);
- FMI 3.0 vs FMI 2.0: the same loop through the FMI 3.0 plant FMU, co-simulation and model
  exchange;
- the FMI 3.0 controller FMU, clocked in Event Mode (:mod:`feeddrive.harness.clocked_controller`),
  against the Python-controller run, with the FMI 2.0 and the FMI 3.0 plant.

Each target is the tolerance of the test that asserts the same agreement (:data:`TARGETS`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from .control import design_model, simulate_linear
from .fmu import Plant, Result
from .fmu3 import DEFAULT_FMU3
from .harness.clocked_controller import DEFAULT_CONTROLLER3_FMU, simulate_clocked
from .harness.controller_fmu import controller_fmu_parameters, sinusoid_source
from .harness.controllers import make_controller, state_space_spec
from .harness.references import sinusoid
from .harness.simulate import RECORD, simulate_closed_loop
from .paper import paper_parameters
from .physics import GMSFriction, applied_force, compile, gms_force

Row = tuple[str, str, str]
AMPLITUDE, PERIOD, CENTRE = 0.030, 6.0, 0.150  #: the Sec. 3 sinusoid [m], [s], [m]
_F_S = float(paper_parameters()["friction.F_s"])

#: figure -> bound, each the tolerance of the test named beside it
TARGETS: dict[str, float] = {
    # tests/test_physics_effects.py: the twin and the FMU in one state agree to 1e-9 N
    "twin_cogging_N": 1e-9,
    "twin_K_f_N_per_A": 1e-9,
    "twin_friction_N": 1e-9,
    "twin_ma_N": 1e-9,
    # test_current_loop_samples_python_equals_fmu: i = G(z) u at the samples to 1e-12 A
    "twin_current_A": 1e-12,
    # tests/test_fmu_prerolling.py: the FMU's friction against Maxwell slip on the same samples
    "gms_along_N": 0.005 * _F_S,
    # tests/test_fmi3.py: TOL_VERSIONS (CS), TOL_X and the CS/ME friction bound (ME, 7 states)
    "fmi3_cs_dx_m": 1e-12,
    "fmi3_me_dx_m": 0.1e-6,
    "fmi3_me_dF_N": 0.05,
    # tests/test_ctrl_clocked.py: the clocked loop is the harness's run to the bit
    "clocked_dx_m": 0.0,
    "clocked_du_V": 0.0,
    "clocked3_dx_m": 0.0,
    "clocked3_du_V": 0.0,
}


def closed_loop(
    duration: float = PERIOD,
    interface: str = "cs",
    path: str | Path | None = None,
    record: Sequence[str] = RECORD,
) -> Result:
    """The loop of ``duration`` s (the Python controller) with the plant FMU at ``path``
    (default: the package's FMI 2.0 one), tolerance 1e-6."""
    ref = sinusoid(AMPLITUDE, PERIOD, CENTRE, duration)
    ctrl = make_controller(state_space_spec(), ref)
    with Plant(paper_parameters(), interface=interface, tolerance=1e-6, path=path) as plant:
        return simulate_closed_loop(plant, ctrl, ref.n, float(ref.x[0]), record=record)


def _max_abs(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b))))


def twin_figures(duration: float = PERIOD) -> dict[str, float]:
    """The twin (:mod:`feeddrive.physics`) in the FMU's recorded state: max abs differences,
    and the largest magnitude of each FMU signal (``peak_*``)."""
    P = compile(paper_parameters())
    n_el = len(P.friction.nu)
    elements = [f"friction.F[{j + 1}]" for j in range(n_el)]
    r = closed_loop(duration, record=list(RECORD) + elements)
    x, v, u = r["x"], r["v"], r["u"]
    F_f = np.sum([r[e] for e in elements], axis=0) + P.friction.viscous(v)
    # row k + 1 is read after step k: the current that step held (r["i"][k], aligned)
    i_held = np.concatenate((r["i"][:1], r["i"][:-1]))
    F_app = applied_force(P.K_f(x) * i_held, P.F_cg(x), r["F_ext"], P.F_offset)
    n0 = 2000  # samples at u[0] before the run: Eq. 2 starts in its steady state
    i_eq2 = P.current.current(np.concatenate((np.full(n0, u[0]), u)))[n0:]
    return {
        "twin_cogging_N": _max_abs(P.F_cg(x), r["F_cogging"]),
        "twin_K_f_N_per_A": _max_abs(P.K_f(x), r["K_f"]),
        "twin_friction_N": _max_abs(F_f, r["F_friction"]),
        "twin_ma_N": _max_abs(F_app - F_f, P.m * r["a"]),
        "twin_current_A": _max_abs(i_eq2[:-1], r["i"][:-1]),  # the last row repeats
        "gms_along_N": _max_abs(gms_force(x, v, P.Ts, P.friction), r["F_friction"]),
        "peak_cogging_N": float(np.max(np.abs(r["F_cogging"]))),
        "peak_K_f_N_per_A": float(np.max(np.abs(r["K_f"]))),
        "peak_friction_N": float(np.max(np.abs(r["F_friction"]))),
        "peak_ma_N": float(P.m * np.max(np.abs(r["a"]))),
        "peak_current_A": float(np.max(np.abs(r["i"]))),
        "samples": float(len(x)),
    }


def design_loop_figures(
    res_cs: Mapping[str, np.ndarray] | None = None, duration: float = PERIOD
) -> dict[str, float]:
    """The design model's loop (:func:`feeddrive.control.simulate_linear`: K_f0 without ripple,
    Eq. 2, the GMS stepper and the cogging held over each sample) against the FMU's loop
    ``res_cs`` (run here when not given): max abs(dx), and the FMU loop's tracking error."""
    h = res_cs if res_cs is not None else closed_loop(duration)
    params = paper_parameters()
    P = compile(params)
    ref = sinusoid(AMPLITUDE, PERIOD, CENTRE, duration)
    gms = GMSFriction(P.friction, ref.Ts, float(ref.x[0]), 0.0)

    def force(k: int, x: float, v: float) -> float:
        return (gms.step(x, v) if k else 0.0) + float(P.F_cg(x))

    ctrl = make_controller(state_space_spec(), ref)
    lin = simulate_linear(
        design_model(params), ctrl, ref.n + 1, x0=float(ref.x[0]), quantum=1e-7, force=force
    )
    x_ref = np.append(ref.x, ref.x[-1])[: ref.n + 1]
    return {
        "design_dx_m": _max_abs(lin["x"], h["x"]),
        "tracking_error_m": _max_abs(h["x"], x_ref),
    }


def version_figures(
    res_cs: Mapping[str, np.ndarray] | None = None,
    res_me: Mapping[str, np.ndarray] | None = None,
    duration: float = PERIOD,
    me: bool = True,
) -> dict[str, float]:
    """The FMI 3.0 plant's loop against the FMI 2.0 plant's (``res_cs``, ``res_me``: the FMI 2.0
    runs of :func:`closed_loop`, run here when not given); model exchange only with ``me``."""
    out: dict[str, float] = {}
    for interface, res2 in (("cs", res_cs), ("me", res_me)):
        if interface == "me" and not me:
            continue
        r2 = res2 if res2 is not None else closed_loop(duration, interface)
        r3 = closed_loop(duration, interface, path=DEFAULT_FMU3)
        out[f"fmi3_{interface}_dx_m"] = _max_abs(r3["x"], r2["x"])
        out[f"fmi3_{interface}_dF_N"] = _max_abs(r3["F_friction"], r2["F_friction"])
    return out


def clocked_figures(
    res_cs: Mapping[str, np.ndarray] | None = None, duration: float = PERIOD
) -> dict[str, float]:
    """The FMI 3.0 controller FMU (clocked) with the FMI 2.0 and the FMI 3.0 plant against the
    Python-controller run ``res_cs`` (FMI 2.0 plant; run here when not given)."""
    h = res_cs if res_cs is not None else closed_loop(duration)
    ref = sinusoid(AMPLITUDE, PERIOD, CENTRE, duration)
    source = sinusoid_source(AMPLITUDE, PERIOD, CENTRE, duration)
    values = controller_fmu_parameters(state_space_spec(), quantum=1e-7, reference=source)
    loop = (paper_parameters(), values, ref.n, float(ref.x[0]))
    out: dict[str, float] = {}
    for key, plant in (("clocked", None), ("clocked3", DEFAULT_FMU3)):
        c = simulate_clocked(*loop, controller_path=DEFAULT_CONTROLLER3_FMU, plant_path=plant)
        out[f"{key}_dx_m"] = _max_abs(c["x"], h["x_measured"])
        out[f"{key}_du_V"] = _max_abs(c["u"], h["u"])
    return out


def agreement_figures(
    res_cs: Mapping[str, np.ndarray] | None = None,
    res_me: Mapping[str, np.ndarray] | None = None,
    duration: float = PERIOD,
    me: bool = True,
) -> dict[str, float]:
    """Every figure of :func:`agreement_rows`; ``res_cs``/``res_me``: the FMI 2.0 runs of the
    loop (CS, ME with CVode rtol 1e-6) when the caller has them."""
    return {
        **twin_figures(duration),
        **design_loop_figures(res_cs, duration),
        **version_figures(res_cs, res_me, duration, me),
        **clocked_figures(res_cs, duration),
    }


def _rel(f: Mapping[str, float], key: str, peak: str) -> str:
    return f"{f[key]:.2g} ({f[key] / f[peak]:.1g} of {f[peak]:.3g})"


def agreement_rows(f: Mapping[str, float]) -> list[Row]:
    """The table rows of the figures ``f`` (:func:`agreement_figures`)."""
    rows: list[Row] = [
        (
            f"Python vs FMU: feeddrive.physics in the FMU's state at each of the {f['samples']:.0f} "
            "samples of the 6 s loop (CS), max abs difference: cogging F_cg(x) / friction "
            "(element forces + viscous) / m a (Eq. 1) [N]",
            f"{_rel(f, 'twin_cogging_N', 'peak_cogging_N')} / "
            f"{_rel(f, 'twin_friction_N', 'peak_friction_N')} / {_rel(f, 'twin_ma_N', 'peak_ma_N')}",
            f"<= {TARGETS['twin_ma_N']:g} N",
        ),
        (
            "  force constant with ripple K_f(x) [N/A]",
            _rel(f, "twin_K_f_N_per_A", "peak_K_f_N_per_A"),
            f"<= {TARGETS['twin_K_f_N_per_A']:g} N/A",
        ),
        (
            "  current, Eq. 2 G(z) on the controller's u [A]",
            _rel(f, "twin_current_A", "peak_current_A"),
            f"<= {TARGETS['twin_current_A']:g} A",
        ),
        (
            "  friction, the twin's GMS integrated along the FMU's x, v samples (gms_force, "
            "virgin start) [N]",
            _rel(f, "gms_along_N", "peak_friction_N"),
            f"<= 0.005 F_s = {TARGETS['gms_along_N']:.3g} N",
        ),
        (
            "  the package's own closed loop (control.simulate_linear: design model, K_f0 "
            "without ripple, GMS stepper + cogging held over each sample) vs the FMU's loop, "
            "max abs(dx)",
            f"{f['design_dx_m'] * 1e6:.3g} um (the FMU loop's tracking error: "
            f"{f['tracking_error_m'] * 1e6:.3g} um)",
            "reported (no test bounds it)",
        ),
        (
            "FMI 3.0 vs FMI 2.0 plant, the 6 s loop from Python, CS: max abs(dx) / "
            "max abs(dF_friction)",
            f"{f['fmi3_cs_dx_m'] * 1e6:.3g} um / {f['fmi3_cs_dF_N']:.3g} N",
            f"<= {TARGETS['fmi3_cs_dx_m']:g} m (x)",
        ),
    ]
    if "fmi3_me_dx_m" in f:
        rows.append(
            (
                "  ME + fmpy CVode rtol 1e-6 (FMI 3.0: 7 states, FMI 2.0: 12): max abs(dx) / "
                "max abs(dF_friction)",
                f"{f['fmi3_me_dx_m'] * 1e6:.3g} um / {f['fmi3_me_dF_N']:.3g} N",
                f"<= {TARGETS['fmi3_me_dx_m'] * 1e6:g} um / {TARGETS['fmi3_me_dF_N']:g} N",
            )
        )
    rows += [
        (
            "FMI 3.0 controller FMU (clocked, Event Mode) + FMI 2.0 plant vs the "
            "Python-controller run: max abs(dx) / max abs(du)",
            f"{f['clocked_dx_m'] * 1e6:.3g} um / {f['clocked_du_V']:.3g} V",
            "0 (to the bit)",
        ),
        (
            "  + FMI 3.0 plant",
            f"{f['clocked3_dx_m'] * 1e6:.3g} um / {f['clocked3_du_V']:.3g} V",
            "0 (to the bit)",
        ),
    ]
    return rows


def within_targets(f: Mapping[str, float]) -> list[str]:
    """The figures of ``f`` beyond their :data:`TARGETS` (empty: all met)."""
    return [f"{k} = {f[k]:.3g} > {t:g}" for k, t in TARGETS.items() if k in f and not f[k] <= t]
