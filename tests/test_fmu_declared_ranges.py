"""Declared ranges that mean something, on both builds of the plant (FMI 2.0 and FMI 3.0):

* a model whose parameters make it unstable or absurd is refused at initialisation naming the
  rule: an unstable current loop (Schur-Cohn test of Eq. 2's denominator, checked against numpy's
  roots), a tolerance looser than solver.tol's declared max (the loosest at which the DP45's error
  still follows its tolerance, measured here at the stiffest declared settings);
* a continuous state leaving its declared [min, max] during a co-simulation step ends the step
  with an error naming the state, its range and the cause; in model exchange the setter of the
  continuous states refuses one beyond its range (the integration stops there); no message prints
  "inf" as a rate;
* a sweep of extreme settings (every parameter and input at its min and at its max alone, and
  random combinations of them): each is refused at initialisation with a message, or runs with
  every step OK and every continuous state inside its declared range, or ends a step with an
  error naming a variable.
"""

from __future__ import annotations

import ctypes
import re
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException

from feeddrive.fmu import FMUError, Plant

H = 1e-3  # s, communication step
DP = ctypes.POINTER(ctypes.c_double)
STATES = (
    ["x", "v"] + [f"friction.F[{j}]" for j in range(1, 11)] + ["compliance.dx", "compliance.dv"]
)
VERSIONS = ("2.0", "3.0")


@pytest.fixture(params=VERSIONS, ids=["fmi2", "fmi3"])
def path(request, fmu2_path: Path, fmu3_path: Path) -> Path:
    return fmu2_path if request.param == "2.0" else fmu3_path


def _run(
    path: Path, params: dict, inputs: dict, t_end: float, tolerance: float = 1e-6
) -> tuple[np.ndarray, Plant]:
    """x, v after every step of H up to t_end (raises FMUError at a refused init or step)."""
    p = Plant(params, path=path, tolerance=tolerance)
    p.start(inputs)
    out = []
    for k in range(int(round(t_end / H))):
        p.do_step(k * H, H)
        g = p.get(["x", "v"])
        out.append((g["x"], g["v"]))
    return np.array(out), p


# ------------------------------------------------------------------ unstable current loop


def _a_from_roots(roots: list[complex]) -> dict:
    """current.a[1..5] of the denominator z^n - a_1 z^(n-1) - ... - a_n with these roots."""
    c = np.real(np.poly(roots))  # 1, c_1 .. c_n: z^n + c_1 z^(n-1) + ...
    a = -c[1:]
    return {f"current.a[{j}]": float(a[j - 1]) if j <= len(a) else 0.0 for j in range(1, 6)}


def test_unstable_current_loop_refused_at_initialisation(path: Path) -> None:
    """current.a[1] = 10 (unchecked: x = 2.5e174 m after 0.1 s) is refused at
    initialisation naming the rule; a loop with a pole pair at |z| = 1.02 is refused, one at
    |z| = 0.98 runs."""
    for params in (
        {"current.a[1]": 10.0},
        _a_from_roots([1.02 * np.exp(0.3j), 1.02 * np.exp(-0.3j), 0.5]),
    ):
        with pytest.raises(
            FMUError, match=r"current\.a\[1\.\.5\].*the current loop is unstable.*\|z\| < 1"
        ):
            _run(path, params, {"u": 1.0}, 0.01)
    xv, p = _run(
        path, _a_from_roots([0.98 * np.exp(0.3j), 0.98 * np.exp(-0.3j), 0.5]), {"u": 1.0}, 0.01
    )
    p.close()
    assert np.all(np.isfinite(xv))


def test_current_loop_rule_agrees_with_the_roots(fmu2_path: Path) -> None:
    """300 random current.a[1..5] of orders 1 to 5 (the roots' moduli spread around 1): the FMU
    refuses exactly those whose denominator has a root with |z| >= 1 (numpy's roots)."""
    rng = np.random.default_rng(7)
    refused = accepted = 0
    for _ in range(300):
        n = int(rng.integers(1, 6))
        a = rng.uniform(-1.0, 1.0, n) * rng.choice([0.5, 1.0, 2.0])
        radius = float(np.max(np.abs(np.roots(np.r_[1.0, -a]))))
        if abs(radius - 1.0) < 1e-6 or abs(1.0 - a.sum()) < 1e-6:
            continue
        params = {f"current.a[{j}]": float(a[j - 1]) if j <= n else 0.0 for j in range(1, 6)}
        p = Plant(params, path=fmu2_path)
        try:
            p.start({"u": 0.0})
            ok = True
        except FMUError as e:
            assert "the current loop is unstable" in str(e), str(e)
            ok = False
        p.close()
        assert ok == (radius < 1.0), (a, radius)
        refused += not ok
        accepted += ok
    print(f"random current loops: {accepted} stable accepted, {refused} unstable refused")
    assert refused > 50 and accepted > 50


# ------------------------------------------------------------------ tolerance


def test_solver_tol_beyond_its_declared_max(path: Path) -> None:
    """solver.tol = 0.99 (with m = 1e-3 kg: v = 3.7e298 m/s after 0.1 s) is refused naming the
    allowed (0, 0.01]; an experiment tolerance of 0.5 integrates at 0.01 (the same trajectory
    to the bit)."""
    with pytest.raises(FMUError, match=r"solver\.tol = 0\.99.*\(0, 0\.01\]"):
        _run(path, {"m": 1e-3, "solver.tol": 0.99}, {"u": 1.0}, 0.01)
    at_max, p = _run(path, {"m": 1e-3}, {"u": 1.0}, 0.02, tolerance=0.01)
    p.close()
    loose, p = _run(path, {"m": 1e-3}, {"u": 1.0}, 0.02, tolerance=0.5)
    assert any("tolerance = 0.5 is looser than 0.01" in m for m in p.messages), p.messages
    p.close()
    np.testing.assert_array_equal(loose, at_max)


@pytest.mark.parametrize(
    "extra", [{}, {f"friction.k[{j}]": 1e9 for j in range(1, 6)}], ids=["m", "m+k"]
)
def test_error_follows_the_tolerance_up_to_its_max(fmu2_path: Path, extra: dict) -> None:
    """At the stiffest declared settings (m = 1e-3 kg; with friction.k = 1e9 N/m), 0.1 s at
    u = 1 V: the velocity's error against tolerance 1e-10 stays within 2 tol (relative to
    max |v|) at tol = 1e-3 and at the declared max 1e-2 (measured 1.1 to 1.2 tol)."""
    params = {"m": 1e-3, **extra}
    ref, p = _run(fmu2_path, params, {"u": 1.0}, 0.1, tolerance=1e-10)
    p.close()
    for tol in (1e-3, 1e-2):
        xv, p = _run(fmu2_path, params, {"u": 1.0}, 0.1, tolerance=tol)
        p.close()
        err = float(np.max(np.abs(xv[:, 1] - ref[:, 1])) / np.max(np.abs(ref[:, 1])))
        print(f"{(extra and 'm, k') or 'm'}: tol {tol:g}: max |dv| / max |v| = {err:.3g}")
        assert err <= 2.0 * tol


# ------------------------------------------------------------------ a state leaving its range


def test_state_leaving_its_range_ends_the_step(path: Path) -> None:
    """F_ext = 1e5 N drives |v| past its declared 1000 m/s (unchecked, to 1175 m/s): the
    step that crosses ends with an error naming v, its range and the forces; every earlier step
    ended with |v| <= 1000 m/s."""
    p = Plant({}, path=path)
    p.start({"F_ext": 1e5})
    vs = []
    with pytest.raises(FMUError) as e:
        for k in range(1000):
            p.do_step(k * H, H)
            vs.append(p.get(["v"])["v"])
    p.close()
    msg = str(e.value)
    assert re.search(
        r"DoStep: v = -?1\d{3}\.\d+ m/s left its declared range \[-1000, 1000\] m/s", msg
    ), msg
    assert "F_ext = 100000 N" in msg and "a = " in msg
    assert vs and max(abs(v) for v in vs) <= 1000.0


def test_state_leaving_its_range_inside_a_long_step(path: Path) -> None:
    """The current loop ideal (no samples) and one step of 1 s: |v| passes 1000 m/s at about
    0.23 s, inside the step; the error names the time of the integrator step that crossed
    (within the solver's largest step Ts of the crossing), not the step's end."""
    p = Plant({"effects.current_dynamics": False}, path=path)
    p.start({"F_ext": 1e5})
    with pytest.raises(FMUError) as e:
        p.do_step(0.0, 1.0)
    p.close()
    m = re.search(
        r"v = (-?[\d.]+) m/s left its declared range \[-1000, 1000\] m/s at t = ([\d.]+) s",
        str(e.value),
    )
    assert m, str(e.value)
    assert 1000.0 < abs(float(m.group(1))) < 1002.0 and 0.2 < float(m.group(2)) < 0.3, str(e.value)


def test_model_exchange_state_beyond_its_range_refused(path: Path) -> None:
    """Model exchange: the importer's integrator sets the states, so fmi2SetContinuousStates /
    fmi3SetContinuousStates refuse v = 1500 m/s naming v and its range (the integration stops
    there); the instance keeps its states and its derivatives answer as before."""
    p = Plant({}, interface="me", path=path)
    p.start({"u": 1.0})
    p.update_discrete_states()
    p.fmu.enterContinuousTimeMode()
    nx = p.md.numberOfContinuousStates
    y, dy0, dy1 = np.zeros(nx), np.zeros(nx), np.zeros(nx)
    p.fmu.getContinuousStates(y.ctypes.data_as(DP), nx)
    p.get_derivatives(dy0.ctypes.data_as(DP), nx)
    bad = y.copy()
    bad[1] = 1500.0
    with pytest.raises(FMICallException):
        p.fmu.setContinuousStates(bad.ctypes.data_as(DP), nx)
    assert "state v = 1500 is out of range: allowed [-1000, 1000] m/s" in p.messages[-1], (
        p.messages[-1]
    )
    p.get_derivatives(dy1.ctypes.data_as(DP), nx)
    p.close()
    np.testing.assert_array_equal(dy1, dy0)


def test_no_rate_printed_as_inf(path: Path) -> None:
    """friction.F_c = 0 with frictional lag: the stiff step's message names friction.F_c and
    says the lag rate has no bound, never "rate inf"."""
    with pytest.raises(FMUError) as e:
        _run(path, {"friction.F_c": 0.0}, {"u": 10.0}, 0.5)
    msg = str(e.value)
    assert "friction.F_c = 0 N" in msg and "has no bound" in msg, msg
    assert not re.search(r"\binf\b", msg), msg


# ------------------------------------------------------------------ the sweep of extreme settings


def _declared(md) -> list:
    """parameters and inputs with a declared min and max (Real and Integer)"""
    return [
        v
        for v in md.modelVariables
        if v.causality in ("parameter", "input")
        and v.type in ("Real", "Integer")
        and v.min is not None
        and v.max is not None
    ]


def _sweep_settings(md, n_random: int, seed: int) -> list[dict]:
    vars_ = _declared(md)
    bools = [
        v.name for v in md.modelVariables if v.causality == "parameter" and v.type == "Boolean"
    ]
    settings = [{v.name: float(v.min) if v.type == "Real" else int(v.min)} for v in vars_]
    settings += [{v.name: float(v.max) if v.type == "Real" else int(v.max)} for v in vars_]
    rng = np.random.default_rng(seed)
    for _ in range(n_random):
        s = {}
        for v in rng.choice(vars_, size=int(rng.integers(2, 7)), replace=False):
            end = v.min if rng.random() < 0.5 else v.max
            s[v.name] = float(end) if v.type == "Real" else int(end)
        for b in rng.choice(bools, size=2, replace=False):
            s[str(b)] = bool(rng.random() < 0.5)
        settings.append(s)
    return settings


def _sweep_one(path: Path, setting: dict, ranges: dict, t_end: float) -> str:
    """'refused', 'clean' or 'step error' (each checked), or the failure found."""
    inputs = {k: v for k, v in setting.items() if k in ("u", "F_ext")}
    params = {k: v for k, v in setting.items() if k not in inputs}
    p = Plant(params, path=path)
    try:
        try:
            p.start({"u": 2.0, **inputs})
        except Exception:  # FMUError at initialisation, fmpy's at a refused set or setup
            return "refused" if p.messages else f"refused without a message: {setting}"
        for k in range(int(round(t_end / H))):
            p.do_step(k * H, H)
            g = p.get(list(ranges))
            bad = [n for n, x in g.items() if not ranges[n][0] <= x <= ranges[n][1]]
            if bad:
                return f"OK with {bad[0]} = {g[bad[0]]} outside {ranges[bad[0]]} at t = {(k + 1) * H}: {setting}"
        return "clean"
    except FMUError as e:
        msg = str(e)
        named = re.search(
            r"(\S+) = \S+ .*(left its declared range|fastest rate|stiffest|no bound)", msg
        ) or re.search(r"samples past", msg)
        return "step error" if named else f"step error naming no variable: {msg}"
    finally:
        p.close()


def test_extreme_settings_refused_or_in_range(fmu2_path: Path) -> None:
    """Every parameter and input with a declared range at its min and at its max (alone), and
    433 random combinations of 2 to 6 of them at an end with two effect switches flipped, 0.1 s
    at u = 2 V: refused at initialisation with a message, or clean (every step OK, every
    continuous state inside its declared range after every step), or a step error naming a
    variable. No setting ends OK outside a declared range."""
    md = read_model_description(str(fmu2_path))
    ranges = {v.name: (float(v.min), float(v.max)) for v in md.modelVariables if v.name in STATES}
    settings = _sweep_settings(md, 433, seed=23)
    tally: dict[str, int] = {"refused": 0, "clean": 0, "step error": 0}
    failures = []
    for s in settings:
        r = _sweep_one(fmu2_path, s, ranges, 0.1)
        if r in tally:
            tally[r] += 1
        else:
            failures.append(r)
    print(f"{len(settings)} extreme settings: {tally}, failures {len(failures)}")
    assert not failures, "\n".join(failures[:10])
    assert len(settings) >= 600 and min(tally.values()) > 0


def test_extreme_settings_fmi3(fmu2_path: Path, fmu3_path: Path) -> None:
    """The FMI 3.0 build on 40 random combinations (the step and its checks are the FMI 2.0
    glue's; the settings by their FMI 2.0 names, friction.N left out): the same three outcomes."""
    md = read_model_description(str(fmu2_path))
    ranges = {
        v.name: (float(v.min), float(v.max)) for v in md.modelVariables if v.name in ("x", "v")
    }
    settings = [s for s in _sweep_settings(md, 60, seed=5)[-60:] if "friction.N" not in s][:40]
    out = [_sweep_one(fmu3_path, s, ranges, 0.05) for s in settings]
    failures = [r for r in out if r not in ("refused", "clean", "step error")]
    assert not failures, "\n".join(failures[:10])
