"""The controller FMU (build/DriveController.fmu) against the Python controllers.

Recorded inputs: a harness closed loop (plant FMU + Python controller) gives x_meas[k] and
u[k]; the controller FMU, driven with the same x_meas (and the reference: its internal
generator, or the preview inputs), must give the same u[k] to 1e-12 V.  The arithmetic is
the Python twins' in the same order, so the agreement is to the last bit, except with a
feedforward: its maps (C: one sin/cos and the angle-addition recurrence; Python: a sin/cos
per term) and exp/pow/tanh (numpy's SIMD routines vs the C library) differ in the last bit.
There u_ff agrees to 1e-13 V, the law given the FMU's u_ff to 1e-12 V, and u directly to the
state-space output's own rounding level (see ``_rounding_level``: its terms are ~1e4 V, so a
last-bit difference in the state is ~1e-11 V).
Also: bad parameters refused (fmi2Error, message naming variable, value and range),
``fmpy validate`` clean, the library links only libc/libm, and the Sec. 3 closed loop run as
two FMUs agrees with the harness's run.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
import zipfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu

from feeddrive.control.feedforward import FeedforwardOptions, feedforward
from feeddrive.fmu import FMUError, Plant
from feeddrive.harness import (
    make_controller,
    pid_lead_spec,
    pid_spec,
    point_to_point,
    simulate_closed_loop,
    sinusoid,
    state_space_spec,
)
from feeddrive.harness.controller_fmu import (
    ControllerFMU,
    controller_fmu_parameters,
    point_to_point_source,
    preview_inputs,
    sinusoid_source,
)
from feeddrive.harness.references import Reference
from feeddrive.harness.two_fmus import simulate_two_fmus
from feeddrive.paper import paper_parameters

REPO = Path(__file__).resolve().parents[1]
CTRL_FMU = REPO / "build" / "DriveController.fmu"
TOL_V = 1e-12
EPS = np.finfo(float).eps

SINE = (0.005, 0.4, 0.15, 1.0)  # amplitude, period, centre, duration: 5 reversals
P2P = (0.13, 0.16, 0.05, 2.0, 0.05)  # x_start, x_end, speed, accel, dwell


@pytest.fixture(scope="module")
def ctrl_fmu(fmu_path) -> Path:
    """build/DriveController.fmu (built by `make fmu` with the plant's)."""
    assert CTRL_FMU.is_file(), f"`make fmu` did not produce {CTRL_FMU}"
    return CTRL_FMU


def _ff(**kw: Any) -> FeedforwardOptions:
    return FeedforwardOptions(**kw)


OFFSET = {"effects.offset_force": True, "offset.F": 3.0}
#: position_friction on the nominal plant: p(x) varies over the sinusoid's 145-155 mm
POSFRIC = {
    "effects.position_friction": True,
    "friction_profile.x_start": 0.14,
    "friction_profile.x_end": 0.16,
    "friction_profile.n": 5,
    **{f"friction_profile.c[{j + 1}]": c for j, c in enumerate([0.0, 0.2, -0.1, 0.3, 0.0])},
}
CASES: dict[str, dict[str, Any]] = {
    "pid": pid_spec(),
    "pid_tf_antiwindup": pid_spec(tf=1e-3, anti_windup=True, u_limit=0.5),
    "pid_lead": pid_lead_spec(),
    "state_space_zpetc": state_space_spec(),
    "state_space_no_prefilter": state_space_spec(prefilter=None),
    "ff_cogging_ripple": state_space_spec(feedforward=_ff(friction="none")),
    "ff_cogging_no_ripple": state_space_spec(feedforward=_ff(friction="none", ripple=False)),
    "ff_inertia": state_space_spec(feedforward=_ff(inertia=True, cogging=False, friction="none")),
    "ff_static": state_space_spec(feedforward=_ff(friction="static")),
    "ff_offset": state_space_spec(OFFSET, feedforward=_ff(friction="none", cogging=False)),
    "ff_gms": state_space_spec(feedforward=_ff(friction="gms")),
    "ff_gms_all": state_space_spec(OFFSET, feedforward=_ff(inertia=True)),
    "ff_static_posfric": state_space_spec(POSFRIC, feedforward=_ff(friction="static")),
    "ff_gms_posfric": state_space_spec(POSFRIC, feedforward=_ff(friction="gms")),
}
#: the cases whose u_ff differs in the last bit (every feedforward: maps, exp, pow, tanh)
TRANSCENDENTAL = {k for k, spec in CASES.items() if spec.get("feedforward")}


def _reference(source: str) -> tuple[Reference, Mapping[str, Any] | None]:
    if source == "sinusoid":
        return sinusoid(*SINE), sinusoid_source(*SINE)
    ref = point_to_point(*P2P)
    return ref, (point_to_point_source(*P2P) if source == "point_to_point" else None)


def _harness(spec: Mapping[str, Any], ref: Reference) -> tuple[np.ndarray, np.ndarray, Any]:
    """x_meas, u of a harness closed loop (plant FMU, Python controller), and the controller."""
    ctrl = make_controller(spec, ref)
    plant_params = dict(paper_parameters())
    plant_params.update((spec.get("feedforward") or {}).get("parameters", {}))
    with Plant(plant_params, interface="cs") as plant:
        res = simulate_closed_loop(plant, ctrl, ref.n, float(ref.x[0]))
    return np.asarray(res["x_meas"]), np.asarray(res["u"]), ctrl


def _drive(
    values: Mapping[str, Any], ref: Reference, x_meas: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """u[k], u_ff[k] of the controller FMU for the recorded x_meas (k = 0..n-1)."""
    P = int(values.get("zpetc.preview", 0)) if values.get("zpetc.on") else 0
    xr, vr, ar = preview_inputs(ref, P)
    u, uff = np.empty(ref.n), np.empty(ref.n)
    with ControllerFMU(values) as c:
        c.start({"x_meas": float(x_meas[0]), "x_ref": float(xr[0])})
        out = c.raw(["u", "u_ff"])
        for k in range(ref.n):
            u[k] = c.step(k, float(x_meas[k]), float(xr[k]), float(vr[k]), float(ar[k]))
        # u_ff of every sample: replay with the same inputs, read after each input is set
        c.start({"x_meas": float(x_meas[0]), "x_ref": float(xr[0])})
        inp = c.raw(["x_meas", "x_ref", "v_ref", "a_ref"])
        r = c.raw_calls()
        for k in range(ref.n):
            inp.set((float(x_meas[k]), float(xr[k]), float(vr[k]), float(ar[k])))
            uff[k] = out.get()[1]
            assert r.do_step(r.component, k * ref.Ts, ref.Ts, 1) <= 1
    return u, uff


def _rounding_level(ctrl: Any, x_meas: np.ndarray, n: int) -> float:
    """max over k of eps * (sum_j |Cc_j s_j| + |Dy y| + |Dr r|): the rounding error of the
    state-space output itself (its terms are ~1e4 V and cancel to ~1 V)."""
    lti = ctrl.lti
    ctrl.reset()
    level = 0.0
    for k in range(n):
        s = np.array(ctrl._s if not ctrl._fresh else [x_meas[k]] + ctrl._s[1:])
        r = ctrl._r[min(k, ctrl._n_r - 1)]
        level = max(
            level,
            float(np.abs(lti["Cc"] * s).sum() + abs(lti["Dy"] * x_meas[k]) + abs(lti["Dr"] * r)),
        )
        ctrl.step(float(x_meas[k]), k)
    return 4 * EPS * level


#: every case on the internal sinusoid; the point-to-point generator and the preview inputs
#: (at rest for the dwell) on one case of each kind
RUNS = [(c, "sinusoid") for c in sorted(CASES)] + [
    (c, s)
    for s in ("point_to_point", "inputs")
    for c in ("pid_lead", "state_space_zpetc", "ff_static", "ff_gms_all")
]


@pytest.mark.parametrize("case, source", RUNS)
def test_recorded_inputs(ctrl_fmu, case: str, source: str) -> None:
    """Every controller type and feedforward option, with each reference source."""
    spec = CASES[case]
    ref, src = _reference(source)
    x_meas, u_py, ctrl = _harness(spec, ref)
    values = controller_fmu_parameters(spec, Ts=ref.Ts, reference=src)
    u, uff = _drive(values, ref, x_meas)
    assert np.all(np.isfinite(u)) and np.ptp(x_meas) > 0.5 * np.ptp(ref.x)
    du = float(np.max(np.abs(u - u_py[: ref.n])))
    print(f"{case}/{source}: max |u_fmu - u_python| = {du:.3g} V")
    if case not in TRANSCENDENTAL:
        assert du <= TOL_V, f"{case}/{source}: max |u_fmu - u_python| = {du:.3g} V"
        return
    ff = spec["feedforward"]
    py_ff = feedforward(
        ref.x,
        ref.Ts,
        ff["parameters"],
        FeedforwardOptions(**ff["options"]),
        v_ref=ref.v,
        a_ref=ref.a,
    ).u
    dff = float(np.max(np.abs(uff - py_ff[: ref.n])))
    assert dff <= 1e-13, f"{case}/{source}: feedforward max |du_ff| = {dff:.3g} V"
    # the law, given the FMU's u_ff: the Python controller without its own feedforward
    bare = dict(spec, feedforward=None)
    c2 = make_controller(bare, ref, u_ff=np.append(uff, 0.0))
    c2.reset()
    u2 = np.array([c2.step(float(x_meas[k]), k) for k in range(ref.n)])
    dl = float(np.max(np.abs(u - u2)))
    assert dl <= TOL_V, f"{case}/{source}: law given u_ff: max |du| = {dl:.3g} V"
    tol = max(TOL_V, _rounding_level(ctrl, x_meas, ref.n))
    assert tol < 1e-10
    print(f"  u_ff {dff:.3g} V, law given u_ff {dl:.3g} V, rounding level {tol:.3g} V")
    assert du <= tol, f"{case}/{source}: max |u_fmu - u_python| = {du:.3g} V > {tol:.3g} V"


def test_circle_component(ctrl_fmu) -> None:
    """A circle's second axis: the sinusoid with phase -pi/2 (x = c - A cos(wt - pi/2))."""
    A, T, c, dur = SINE
    values = controller_fmu_parameters(
        pid_spec(), reference=sinusoid_source(A, T, c, dur, -np.pi / 2)
    )
    n = int(round(dur / 5e-4))
    with ControllerFMU(values) as fmu:
        fmu.start({"x_meas": c})
        out = fmu.raw(["r_x"])
        rx = []
        for k in range(n):
            fmu._inp.set((c, 0.0, 0.0, 0.0))
            rx.append(float(out.get()[0]))
            fmu.step(k, c)
    t = np.arange(n) * 5e-4
    np.testing.assert_allclose(rx, c - A * np.sin(2 * np.pi * t / T), rtol=0, atol=1e-15)


# ---------------------------------------------------------------- bad parameters
def _refused(values: Mapping[str, Any], set_after: Mapping[str, Any] | None = None) -> str:
    """Start the FMU with ``values`` (then set ``set_after`` between steps); the refusal's
    message."""
    with ControllerFMU({}) as c:
        with pytest.raises(FMUError) as err:
            c.start(values)
            if set_after:
                c.step(0, 0.15)
                c.set(set_after)
        return str(err.value)


@pytest.mark.parametrize(
    "values, name, value, rng",
    [
        ({"pid.Kp": -1.0}, "pid.Kp", "-1", "[0, "),
        ({"ctrl.type": 5}, "ctrl.type", "5", "4]"),
        ({"ss.n": 9}, "ss.n", "9", "8]"),
        ({"zpetc.preview": 65}, "zpetc.preview", "65", "64]"),
        ({"ff.friction": 3}, "ff.friction", "3", "2]"),
        ({"x_meas": float("nan")}, "x_meas", "nan", "finite"),
        (
            {"ctrl.type": 3, "lead.zero_hz": 200.0},
            "lead.zero_hz",
            "200",
            "(0, lead.pole_hz = 120) Hz",
        ),
        ({"ctrl.type": 3, "lead.pole_hz": 1500.0}, "lead.pole_hz", "1500", "1000) Hz (Nyquist)"),
        (
            {"ctrl.type": 3, "lead.zero_hz": 1e-320},
            "lead.zero_hz",
            "9.9998886718268301e-321",
            "not finite",
        ),
        ({"u_limit": 0.0}, "u_limit", "0", "(0, 1e6] V"),
        (
            {"pid.force_per_volt": 0.0},
            "pid.force_per_volt",
            "0",
            "allowed [1.0000000000000001e-09, ",
        ),
        (
            {"scale.quantum": 1e-300},
            "scale.quantum",
            "1e-300",
            "allowed 0 (no quantisation) or [1e-12, 1] m",
        ),
        (
            {"ref.source": 1, "ref.period": 0.0},
            "ref.period",
            "0",
            "allowed [1.0000000000000001e-09, 1000000000] s",
        ),
        ({"ref.source": 2, "ref.x_end": 0.13}, "ref.x_end", "0.13", "but ref.x_start"),
        ({"ff.on": True, "ff.friction": 1, "ff.v_eps": 0.0}, "ff.v_eps", "0", "(0, 1000] m/s"),
        ({"ff.on": True, "plant.friction.nu[2]": 1.5}, "plant.friction.nu[2]", "1.5", "[0, 1]"),
        ({"ff.on": True, "plant.friction.F_c": 40.0}, "plant.friction.F_c", "40", "allowed"),
        ({"zpetc.on": True, "zpetc.a[1]": 2.0}, "zpetc.a[1]", "2", "allowed 1"),
    ],
)
def test_bad_parameters_refused(ctrl_fmu, values, name: str, value: str, rng: str) -> None:
    msg = _refused(values)
    assert name in msg and f"= {value}" in msg and rng in msg, msg


def test_bad_tunable_between_steps_changes_nothing(ctrl_fmu) -> None:
    """A refused tunable change mid-run leaves the controller as it was."""
    with ControllerFMU({}) as c:
        c.start({"x_meas": 0.15})
        u0 = [c.step(k, 0.15 - 1e-6 * k) for k in range(10)]
        for bad in ({"u_limit": -1.0}, {"pid.Kv": float("inf")}):
            with pytest.raises(FMUError) as err:
                c.set(bad)
            assert next(iter(bad)) in str(err.value)
        u1 = [c.step(k, 0.15 - 1e-6 * k) for k in range(10, 20)]
    with ControllerFMU({}) as c:
        c.start({"x_meas": 0.15})
        ref = [c.step(k, 0.15 - 1e-6 * k) for k in range(20)]
    assert u0 + u1 == ref


def test_status_is_fmi2error(ctrl_fmu) -> None:
    """The refusal is the FMI status fmi2Error (3), with the message logged."""
    with ControllerFMU({}) as c:
        c.start()
        with pytest.raises(FMICallException) as err:
            c.fmu.setReal([c.vr("pid.Kp")], [-2.0])
        assert err.value.status == 3
        assert "pid.Kp = -2" in c.messages[-1]


# ---------------------------------------------------------------- the FMU file
def test_fmpy_validate(ctrl_fmu) -> None:
    assert validate_fmu(str(ctrl_fmu)) == []


def test_links_only_libc_libm(ctrl_fmu) -> None:
    if shutil.which("ldd") is None:
        pytest.skip("no ldd")
    with tempfile.TemporaryDirectory() as d:
        with zipfile.ZipFile(ctrl_fmu) as z:
            z.extract("binaries/linux64/DriveController.so", d)
        out = subprocess.run(
            ["ldd", str(Path(d) / "binaries/linux64/DriveController.so")],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
    libs = [ln.split()[0] for ln in out.splitlines() if ln.strip()]
    extra = [
        lib
        for lib in libs
        if not any(s in lib for s in ("linux-vdso", "libc.so", "libm.so", "ld-linux"))
    ]
    assert not extra, out


def test_plant_parameters_imported_from_plant_xml(ctrl_fmu, fmu_path) -> None:
    """plant.* of the controller are the plant's parameters (same starts): one source."""
    from fmpy import read_model_description

    plant = {
        v.name: v
        for v in read_model_description(str(fmu_path)).modelVariables
        if v.causality == "parameter"
    }
    ctrl = {
        v.name[len("plant.") :]: v
        for v in read_model_description(str(ctrl_fmu)).modelVariables
        if v.name.startswith("plant.")
    }
    assert set(ctrl) == set(plant)
    assert all(ctrl[k].start == plant[k].start and ctrl[k].type == plant[k].type for k in plant)


# ---------------------------------------------------------------- the system
def test_sec3_two_fmus_agree_with_harness(ctrl_fmu) -> None:
    """The 6 s Sec. 3 sinusoid (30 mm) as controller FMU + plant FMU (macro step Ts, u[k]
    from x(t_k), the harness's convention) is the harness's run to the last bit."""
    ref = sinusoid(0.030, 6.0, 0.150, 6.0)
    spec = state_space_spec()
    with Plant(paper_parameters(), interface="cs") as plant:
        res = simulate_closed_loop(plant, make_controller(spec, ref), ref.n, float(ref.x[0]))
    values = controller_fmu_parameters(
        spec, reference=sinusoid_source(0.030, 6.0, 0.150, 6.0), quantum=1e-7
    )
    two = simulate_two_fmus(paper_parameters(), values, ref.n, float(ref.x[0]))
    assert float(np.max(np.abs(two["x"] - res["x"]))) <= 1e-14  # 0.01 um asked; bitwise here
    assert float(np.max(np.abs(two["u"] - res["u"]))) <= TOL_V


def test_sources_listed_shipped_and_rebuildable(ctrl_fmu, tmp_path) -> None:
    """<SourceFiles> names the controller's C files (its FMI 3.0 clock apart), the FMI glue's
    (FMI 3.0 apart), the plant physics it shares and the two generated tables; each is in
    sources/, and `fmpy compile` rebuilds a binary that gives the same u."""
    import xml.etree.ElementTree as ET

    listed = {
        f.get("name")
        for f in ET.parse(REPO / "fmu_src" / "models" / "controller" / "modelDescription.xml")
        .getroot()
        .find("CoSimulation")
        .find("SourceFiles")
    }
    expected = (
        {
            p.name
            for p in (REPO / "fmu_src" / "models" / "controller").glob("*.c")
            if p.name != "ctrl_clock.c"
        }
        | {p.name for p in (REPO / "fmu_src" / "fmi").glob("*.c") if not p.name.startswith("fmi3")}
        | {
            "params.c",
            "effects.c",
            "current_loop.c",
            "position_maps.c",
            "friction_levels.c",
            "friction_gms.c",
            "friction_position.c",
            "offset_force.c",
            "compliance.c",
            "ctrl_vars.c",
            "model_vars.c",
        }
    )
    assert listed == expected
    shipped = {
        Path(n).name for n in zipfile.ZipFile(ctrl_fmu).namelist() if n.startswith("sources/")
    }
    assert expected <= shipped
    if shutil.which("cmake") is None:
        pytest.skip("cmake is not installed: fmpy compile needs it")
    copy = tmp_path / ctrl_fmu.name
    shutil.copy(ctrl_fmu, copy)
    fmpy_cli = Path(sys.executable).with_name("fmpy")
    p = subprocess.run(
        [str(fmpy_cli), "compile", str(copy)], capture_output=True, text=True, timeout=600
    )
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    ref = sinusoid(*SINE)
    spec = CASES["ff_gms_all"]
    values = controller_fmu_parameters(spec, reference=sinusoid_source(*SINE))
    x_meas = ref.x + 1e-6 * np.sin(np.arange(len(ref.x)))
    us = []
    for path in (ctrl_fmu, copy):
        with ControllerFMU(values, path=path) as c:
            c.start({"x_meas": float(x_meas[0])})
            us.append(np.array([c.step(k, float(x_meas[k])) for k in range(ref.n)]))
    assert float(np.max(np.abs(us[0] - us[1]))) <= TOL_V


# ---------------------------------------------------------------- bounded work, finite answers
def test_step_budget_refuses_before_any_sample(ctrl_fmu) -> None:
    """0.1 s at Ts = 1 ns (its declared minimum) is 1e8 samples, past the budget of 1e6 per
    call: fmi2Error naming the rule, the time unchanged; 1e-5 s (1e4 samples) then steps."""
    with ControllerFMU({"Ts": 1e-9}) as c:
        c.start({"x_meas": 0.15})
        r = c.raw_calls()
        assert r.do_step(r.component, 0.0, 0.1, 1) == 3
        assert "spans 100000000 samples of Ts = 1e-09 s: allowed at most 1000000" in c.messages[-1]
        assert r.do_step(r.component, 0.0, 1e-5, 1) == 0


def test_unstable_state_space_ends_with_an_error_not_nan(ctrl_fmu) -> None:
    """Ac = 1.5 I on two states, By = [1, 2], Cc = [1, -1], x_meas = 0.15 m held: the states grow
    as 1.5^k until one overflows, where u would be inf - inf = NaN. Every u answered is finite
    and the sample whose update overflows (found by running the same recursion in Python, the
    C's operations in its order) is the one refused, naming the state."""
    values = {
        "ctrl.type": 1,
        "ss.n": 2,
        "ss.Ac[1,1]": 1.5,
        "ss.Ac[2,2]": 1.5,
        "ss.By[1]": 1.0,
        "ss.By[2]": 2.0,
        "ss.Cc[1]": 1.0,
        "ss.Cc[2]": -1.0,
    }
    y, s1, s2, k_bad = 0.15, 0.15, 0.0, 0
    with np.errstate(over="ignore"):
        while np.isfinite(s1) and np.isfinite(s2):
            s1, s2 = (
                np.float64(1.5) * s1 + 0.0 * s2 + 1.0 * y,
                0.0 * s1 + np.float64(1.5) * s2 + 2.0 * y,
            )
            k_bad += 1
    k_bad -= 1  # sample k updates the state to s[k + 1]
    us: list[float] = []
    with ControllerFMU(values) as c:
        c.start({"x_meas": y})
        with pytest.raises(FMUError) as err:
            for k in range(k_bad + 10):
                us.append(c.step(k, y))
    assert len(us) == k_bad and 1700 < k_bad < 1800, (len(us), k_bad)
    assert np.isfinite(us).all() and us[-1] == -10.0  # saturated at -u_limit before the overflow
    msg = str(err.value)
    assert (
        f"sample {k_bad} " in msg and "state-space state s[" in msg and "= inf is not finite" in msg
    ), msg
