"""The plant (and the controller) as FMI 3.0 FMUs beside the FMI 2.0 ones: one
variable list, the same trajectories, Configuration Mode for friction.N, early return / event
mode at friction switches on the 6 s closed loop, FMU state serialisation, the exported
functions.

Agreement between the versions is asserted to 1e-12 m: co-simulation runs
the same fmi2DoStep step (fmu_cs_do_step) and model exchange the same right-hand side, so
the only difference left is the integrator's: fmpy's CVode sees 2 + N states in FMI 3.0 and
12 in FMI 2.0 (the unused element slots), and its error norm (a root-mean-square over the
states) differs; with N = 10 (Configuration Mode) the state vectors are the same.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

from conftest import REPO
from feeddrive.fmu3 import configured, fmi3_values, set_values, with_dimension
from feeddrive.harness.two_fmus import simulate_two_fmus
from feeddrive.paper import paper_parameters
from feeddrive.physics.friction_curves import stribeck_level
from fmi3_loops import TS, reference_6s, two_fmus3

CTRL3 = REPO / "build" / "DriveController3.fmu"
TOL_VERSIONS = 1e-12  # m, FMI 3.0 against FMI 2.0 on the same input
TOL_X = 0.1e-6  # m, co-simulation against model exchange (test_cs_agreement's)
T_OPEN = 0.3  # s of open-loop drive, 7 slip-to-stick switches
TYPES = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean"}
N_ARRAYS = {"friction.F", "der(friction.F)", "friction.nu", "friction.k", "friction.stuck"}


def _drive() -> np.ndarray:
    """u = 1.2 V sin(2 pi 3 t): the stage breaks away, reverses, sticks (open loop, 0.3 s)."""
    t = np.arange(0.0, T_OPEN + 1e-12, TS)
    return np.array(
        [(ti, 1.2 * np.sin(2 * np.pi * 3 * ti), 0.0) for ti in t],
        dtype=[("time", float), ("u", float), ("F_ext", float)],
    )


OUT = ["x", "v", "F_friction", "n_stuck"]


# ------------------------------------------------------------------ one variable list


def test_both_descriptions_come_from_the_one_variable_list(fmu_path: Path, fmu3_path: Path) -> None:
    """Every FMI 2.0 variable is in the FMI 3.0 description with its name, value reference,
    unit, start, min, max and nominal: as itself, or as element k of an array of dimension
    friction.N (value reference of element 1, start of the first N elements)."""
    root2 = ET.parse(REPO / "modelDescription.xml").getroot()
    shipped2 = ET.fromstring(zipfile.ZipFile(fmu_path).read("modelDescription.xml"))
    assert ET.tostring(shipped2.find("ModelVariables")) == ET.tostring(root2.find("ModelVariables"))
    md3 = read_model_description(str(fmu3_path))
    v3 = {v.name: v for v in md3.modelVariables}
    n = int(v3["friction.N"].start)
    assert v3["friction.N"].causality == "structuralParameter" and n == 5
    seen = set()
    for sv in root2.find("ModelVariables").findall("ScalarVariable"):
        name, t = sv.get("name"), sv[0]
        m = re.fullmatch(r"(der\()?(.*)\[(\d+)\](\))?", name)
        base = (f"der({m.group(2)})" if m.group(1) else m.group(2)) if m else name
        if base in N_ARRAYS:
            k = int(m.group(3))
            var = v3[base]
            assert [d.valueReference for d in var.dimensions] == [
                v3["friction.N"].valueReference
            ], base
            if k == 1:
                assert var.valueReference == int(sv.get("valueReference")), base
            if t.get("start") is not None and k <= n:
                assert var.start.split()[k - 1] == t.get("start"), name
        else:
            var = v3[name]
            assert var.valueReference == int(sv.get("valueReference")), name
            if t.get("start") is not None:
                want = t.get("start")
                assert str(var.start) == want, name
        seen.add(var.name)
        assert var.type == TYPES[t.tag], name
        assert var.unit == t.get("unit"), name
        for attr in ("min", "max", "nominal"):
            if t.get(attr) is not None:
                assert float(getattr(var, attr)) == float(t.get(attr)), (name, attr)
        assert var.causality == (
            "structuralParameter" if name == "friction.N" else sv.get("causality", "local")
        ), name
        assert var.variability == sv.get("variability", "continuous"), name
    assert set(v3) - seen == {"time", "eventIndicators"}
    assert md3.numberOfEventIndicators == int(root2.get("numberOfEventIndicators"))
    assert md3.guid == root2.get("guid")  # the instantiationToken: states load across versions


# ------------------------------------------------------------------ FMI 3.0 against FMI 2.0


def test_co_simulation_fmi3_equals_fmi2(fmu_path: Path, fmu3_path: Path) -> None:
    r = [
        fmpy.simulate_fmu(
            str(p),
            fmi_type="CoSimulation",
            stop_time=T_OPEN,
            output_interval=TS,
            input=_drive(),
            output=OUT + ["stats.n_stick"],
        )
        for p in (fmu_path, fmu3_path)
    ]
    dx = float(np.max(np.abs(r[0]["x"] - r[1]["x"])))
    print(f"CS, FMI 3.0 vs 2.0: max |dx| = {dx:.3g} m")
    assert dx <= TOL_VERSIONS
    assert np.array_equal(r[0]["n_stuck"], r[1]["n_stuck"]) and r[0]["stats.n_stick"][-1] >= 5


def test_model_exchange_fmi3_equals_fmi2(fmu_path: Path, fmu3_path: Path) -> None:
    """CVode on the same 12 states (FMI 3.0 with friction.N = 10, elements 6..10 at nu = 0:
    the physics of N = 5): to 1e-12 m.  At the default N = 5 (7 states) CVode's steps differ:
    within the CS/ME tolerance."""
    kw = {
        "fmi_type": "ModelExchange",
        "stop_time": T_OPEN,
        "output_interval": TS,
        "input": _drive(),
        "output": OUT,
        "relative_tolerance": 1e-9,
    }
    r2 = fmpy.simulate_fmu(str(fmu_path), **kw)
    md, fmu = configured(fmu3_path, "ModelExchange", 10)
    r10 = fmpy.simulate_fmu(
        str(fmu3_path),
        model_description=md,
        fmu_instance=fmu,
        start_values={
            "friction.nu": [0.17, 0.13, 0.3, 0.017, 0.383, 0, 0, 0, 0, 0],
            "friction.k": [1152070.0, 377230.0, 215330.0, 9390.0, 87660.0] + [100000.0] * 5,
        },
        **kw,
    )
    r5 = fmpy.simulate_fmu(str(fmu3_path), **kw)
    d10 = float(np.max(np.abs(r2["x"] - r10["x"])))
    d5 = float(np.max(np.abs(r2["x"] - r5["x"])))
    print(
        f"ME (CVode rtol 1e-9), FMI 3.0 vs 2.0: max |dx| = {d10:.3g} m (N = 10, 12 states), "
        f"{d5:.3g} m (N = 5, 7 states)"
    )
    assert d10 <= TOL_VERSIONS
    assert d5 <= TOL_X
    assert np.array_equal(r2["n_stuck"], r10["n_stuck"])


@pytest.mark.parametrize("rtol", [1e-10])
def test_co_simulation_agrees_with_model_exchange(
    fmu_version: tuple[Path, str], rtol: float
) -> None:
    """The FMU's own DP45 (CS) against fmpy's CVode (ME) at the same tolerance, both versions."""
    path, version = fmu_version
    kw = {
        "stop_time": T_OPEN,
        "output_interval": TS,
        "input": _drive(),
        "output": OUT,
        "relative_tolerance": rtol,
    }
    cs = fmpy.simulate_fmu(str(path), fmi_type="CoSimulation", **kw)
    me = fmpy.simulate_fmu(str(path), fmi_type="ModelExchange", record_events=False, **kw)
    dx = float(np.max(np.abs(cs["x"] - me["x"])))
    dF = float(np.max(np.abs(cs["F_friction"] - me["F_friction"])))
    print(f"FMI {version}, CS vs ME (rtol {rtol:g}): max |dx| = {dx:.3g} m, max |dF| = {dF:.3g} N")
    assert dx <= TOL_X and dF <= 0.05


@pytest.mark.parametrize("interface", ["CoSimulation", "ModelExchange"])
def test_steady_sliding_friction_both_versions(
    fmu_version: tuple[Path, str], interface: str, paper: dict
) -> None:
    """Mass + friction (cogging, ripple, current loop off) pushed by F_ext = -40 N: the stage
    slides at the speed where the friction balances the push, F_f = S(v) + sigma2 v = 40 N
    (Eqs. 8, 10; S the Stribeck level), every element slipping.  The approach is exponential
    with tau ~ m / sigma2 = 0.3 s: after 2.5 s 18 N e^-8.4 = 0.004 N remain (0.01 N allowed);
    in steady sliding the GMS force equals the curve (1e-6 N)."""
    path, _ = fmu_version
    sv = {
        "effects.cogging_periodic": False,
        "effects.cogging_aperiodic": False,
        "effects.ripple_periodic": False,
        "effects.ripple_aperiodic": False,
        "effects.current_dynamics": False,
        "F_ext": -40.0,
        "x": 0.0,
        "stroke.x_min": -1.0,
        "stroke.x_max": 1.0,
    }
    r = fmpy.simulate_fmu(
        str(path),
        fmi_type=interface,
        stop_time=2.5,
        output_interval=1e-3,
        start_values=sv,
        output=["v", "F_friction", "n_stuck"],
        relative_tolerance=1e-8,
    )
    v, F = float(r["v"][-1]), float(r["F_friction"][-1])
    S = float(
        stribeck_level(
            v,
            paper["friction.F_s"],
            paper["friction.F_c"],
            paper["friction.V_s"],
            paper["friction.delta"],
        )
    )
    assert abs(F - (S + paper["friction.sigma2"] * v)) < 1e-6
    assert abs(F - 40.0) < 0.01 and 0.3 < v < 0.4
    assert r["n_stuck"][-1] == 0


# ------------------------------------------------------------------ friction.N


def test_configuration_mode_sets_the_dimension(fmu3_path: Path) -> None:
    """N = 3: 7 continuous states (x, v, friction.F[1..3], compliance.dx, compliance.dv), arrays
    of 3, and fmpy runs it (model exchange, CVode)."""
    md, fmu = configured(fmu3_path, "ModelExchange", 3)
    assert md.numberOfContinuousStates == 7 and fmu.getNumberOfContinuousStates() == 7
    sv = fmi3_values(
        md,
        {
            "friction.nu[1]": 0.3,
            "friction.nu[2]": 0.3,
            "friction.nu[3]": 0.4,
            "friction.nu[4]": 0.0,
            "friction.k[2]": 4e5,
        },
    )
    assert sv["friction.nu"] == [0.3, 0.3, 0.4] and sv["friction.k"][1] == 4e5
    r = fmpy.simulate_fmu(
        str(fmu3_path),
        model_description=md,
        fmu_instance=fmu,
        fmi_type="ModelExchange",
        stop_time=0.2,
        output_interval=TS,
        input=_drive(),
        start_values=sv,
        output=["x", "n_stuck", "friction.F"],
        relative_tolerance=1e-8,
    )
    assert r["friction.F"].shape == (len(r), 3)
    assert 0 <= r["n_stuck"].min() and r["n_stuck"].max() == 3
    assert np.all(np.isfinite(r["x"]))


def test_structural_parameter_only_in_configuration_mode(fmu3_path: Path) -> None:
    md = read_model_description(str(fmu3_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    log: list[str] = []
    fmu = FMU3Slave(
        guid=md.guid,
        unzipDirectory=extract(str(fmu3_path)),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="n",
    )
    fmu.instantiate(logMessage=lambda env, st, cat, msg: log.append(msg.decode()))
    with pytest.raises(FMICallException):
        fmu.setInt32([vr["friction.N"]], [3])
    assert "friction.N is structural: set it in Configuration Mode" in log[-1]
    fmu.enterConfigurationMode()
    with pytest.raises(FMICallException):
        fmu.setInt32([vr["friction.N"]], [11])
    assert re.search(r"friction\.N = 11.*\[1, 10\]", log[-1]), log[-1]
    with pytest.raises(FMICallException):
        fmu.setFloat64([vr["m"]], [20.0])
    assert "only the structural parameter friction.N" in log[-1]
    fmu.setInt32([vr["friction.N"]], [2])
    fmu.exitConfigurationMode()
    with pytest.raises(FMICallException):  # friction.nu now has 2 elements
        fmu.setFloat64([vr["friction.nu"]], [0.5, 0.3, 0.2])
    assert "nValues = 3" in log[-1] and "friction.N = 2" in log[-1]
    fmu.setFloat64([vr["friction.nu"]], [0.6, 0.4])
    fmu.enterInitializationMode(startTime=0.0)
    fmu.exitInitializationMode()
    assert list(fmu.getFloat64([vr["friction.nu"]], nValues=2)) == [0.6, 0.4]
    assert list(fmu.getBoolean([vr["friction.stuck"]], nValues=2)) == [True, True]
    fmu.terminate()
    fmu.freeInstance()
    with pytest.raises(ValueError, match=r"friction\.N = 0: allowed an integer in \[1, 10\]"):
        with_dimension(md, 0)


# ------------------------------------------------------------------ early return, 6 s loop


@pytest.fixture(scope="module")
def loop_6s(fmu_path: Path, fmu3_path: Path) -> dict:
    n, x0, values = reference_6s()
    ref = simulate_two_fmus(paper_parameters(), values, n, x0, plant_path=fmu_path)
    runs = {
        (er, em): two_fmus3(str(fmu3_path), n, x0, values, early_return=er, event_mode=em)
        for er, em in [(False, False), (True, False), (False, True), (True, True)]
    }
    both3 = two_fmus3(
        str(fmu3_path), n, x0, values, early_return=True, event_mode=True, controller3=str(CTRL3)
    )
    return {"ref": ref, "runs": runs, "n": n, "both3": both3}


def test_closed_loop_fmi3_equals_fmi2_with_and_without_early_return(loop_6s: dict) -> None:
    """Controller FMU + plant FMU, 6 s (12 000 samples): the FMI 3.0 plant without event mode,
    with early return, with event mode and with both gives the FMI 2.0 plant's x to 1e-12 m
    (the early-returned step ends on the state the full step had at the switch)."""
    for (er, em), r in loop_6s["runs"].items():
        dx = float(np.max(np.abs(r.x - loop_6s["ref"]["x"])))
        print(
            f"6 s loop, early return {er}, event mode {em}: max |dx| vs FMI 2.0 = {dx:.3g} m, "
            f"{r.early_returns} early returns, {r.events} event-mode entries, {r.do_steps} fmi3DoStep calls"
        )
        assert dx <= TOL_VERSIONS


def test_closed_loop_of_two_fmi3_fmus_equals_the_fmi2_pair(loop_6s: dict) -> None:
    """The controller FMU as FMI 3.0 too (DriveController3.fmu, over the same C): x to 1e-12 m."""
    r = loop_6s["both3"]
    dx = float(np.max(np.abs(r.x - loop_6s["ref"]["x"])))
    print(
        f"6 s loop, controller and plant FMI 3.0 (early return, event mode): max |dx| = {dx:.3g} m"
    )
    assert dx <= TOL_VERSIONS and r.early_returns == loop_6s["runs"][(True, True)].early_returns


def test_controller_fmi3_validates_and_refuses_what_it_lacks(fmu_path: Path) -> None:
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(CTRL3)) == []
    md = read_model_description(str(CTRL3))
    assert md.fmiVersion == "3.0" and md.modelExchange is None and md.coSimulation.hasEventMode
    log: list[str] = []
    fmu = FMU3Slave(
        guid=md.guid,
        unzipDirectory=extract(str(CTRL3)),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="c3",
    )
    fmu.instantiate(logMessage=lambda env, st, cat, msg: log.append(msg.decode()))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    with pytest.raises(FMICallException):
        fmu.setFloat64([vr["Ts"]], [-1.0])
    assert log[-1].startswith("fmi3SetFloat64: ") and "Ts" in log[-1]
    with pytest.raises(FMICallException):
        fmu.getFMUState()
    assert "fmi3GetFMUState: canGetAndSetFMUState is false" in log[-1]
    fmu.freeInstance()


def test_early_return_at_every_switch_inside_a_step(loop_6s: dict) -> None:
    """An early return for every macro step with a friction switch inside it (the steps that
    event mode alone flags), each at a time strictly inside its step."""
    runs = loop_6s["runs"]
    n_early = runs[(True, False)].early_returns
    assert n_early > 0
    assert (
        n_early
        == runs[(False, True)].events
        == runs[(True, True)].early_returns
        == runs[(True, True)].events
    )
    assert runs[(False, False)].early_returns == runs[(False, False)].events == 0
    assert runs[(True, False)].do_steps == loop_6s["n"] + n_early
    for t in runs[(True, False)].switch_times:
        k = np.floor(t / TS + 1e-9)
        assert k * TS < t < (k + 1) * TS, t


# ------------------------------------------------------------------ FMU state


def _cs3(path: Path, log: list[str]) -> tuple[FMU3Slave, dict]:
    md = read_model_description(str(path))
    fmu = FMU3Slave(
        guid=md.guid,
        unzipDirectory=extract(str(path)),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="s3",
    )
    fmu.instantiate(logMessage=lambda env, st, cat, msg: log.append(msg.decode()))
    set_values(fmu, md, {"u": 1.0})
    fmu.enterInitializationMode(startTime=0.0)
    fmu.exitInitializationMode()
    return fmu, {v.name: v.valueReference for v in md.modelVariables}


def _steps(fmu, t0: float, n: int, x_vr: int, fmi3: bool = True) -> float:
    for k in range(n):
        fmu.doStep(t0 + k * TS, TS)
    return (fmu.getFloat64 if fmi3 else fmu.getReal)([x_vr])[0]


def test_serialised_state_restores_the_trajectory(fmu_path: Path, fmu3_path: Path) -> None:
    """fmi3GetFMUState/Serialize at 0.05 s, on to 0.1 s; Deserialize/SetFMUState and on again:
    the same x to the bit.  The bytes are those of the FMI 2.0 format (same header, CRC): an
    FMI 2.0 co-simulation state loads into the FMI 3.0 instance and continues identically; a
    flipped byte is refused (checksum) and changes nothing."""
    log: list[str] = []
    fmu, vr = _cs3(fmu3_path, log)
    _steps(fmu, 0.0, 100, vr["x"])
    blob = fmu.serializeFMUState(fmu.getFMUState())
    x_a = _steps(fmu, 0.05, 100, vr["x"])
    fmu.setFMUState(fmu.deserializeFMUState(blob))
    x_b = _steps(fmu, 0.05, 100, vr["x"])
    assert x_a == x_b
    bad = bytearray(blob)
    bad[-9] ^= 0x10
    with pytest.raises(FMICallException):
        fmu.deserializeFMUState(bytes(bad))
    assert "checksum" in log[-1]
    # the FMI 2.0 FMU's state of the same run
    md2 = read_model_description(str(fmu_path))
    f2 = FMU2Slave(
        guid=md2.guid,
        unzipDirectory=extract(str(fmu_path)),
        modelIdentifier=md2.coSimulation.modelIdentifier,
        instanceName="s2",
    )
    f2.instantiate()
    f2.setupExperiment(startTime=0.0)
    vr2 = {v.name: v.valueReference for v in md2.modelVariables}
    f2.setReal([vr2["u"]], [1.0])
    f2.enterInitializationMode()
    f2.exitInitializationMode()
    _steps(f2, 0.0, 100, vr2["x"], fmi3=False)
    blob2 = f2.serializeFMUstate(f2.getFMUstate())
    f2.terminate()
    f2.freeInstance()
    assert len(blob2) == len(blob)
    fmu.setFMUState(fmu.deserializeFMUState(blob2))
    assert _steps(fmu, 0.05, 100, vr["x"]) == x_a
    fmu.terminate()
    fmu.freeInstance()


# ------------------------------------------------------------------ the binary


@pytest.mark.parametrize("which", ["plant", "controller"])
def test_library_exports_every_fmi3_function_and_only_those(
    fmu3_path: Path, tmp_path: Path, which: str
) -> None:
    if shutil.which("nm") is None:
        pytest.skip("nm (binutils) is not installed")
    d = Path(extract(str(fmu3_path if which == "plant" else CTRL3), unzipdir=str(tmp_path)))
    so = next(d.glob("binaries/x86_64-linux/*.so"))
    out = subprocess.run(
        ["nm", "-D", "--defined-only", str(so)], capture_output=True, text=True, check=True
    ).stdout
    exported = {line.split()[-1] for line in out.splitlines() if line.strip()}
    header = (Path(fmpy.__file__).parent / "c-code" / "fmi3Functions.h").read_text()
    declared = set(re.findall(r"FMI3_Export\s+fmi3\w+TYPE\s+(fmi3\w+)\s*;", header))
    assert len(declared) >= 70
    assert exported == declared, (sorted(exported - declared), sorted(declared - exported))


def test_every_fmi3_entry_point_enters_through_the_one_table() -> None:
    """Each fmi3 function of fmu_src/fmi/fmi3*.c that takes an instance starts with
    FMU_ENTER(<instance>, <its name or a catch-all of the table>) or answers through
    fmi3_refuse (which enters through the table's fmi3NotProvided), and every FMU_ENTER names
    an entry of allowed.h."""
    table = set(
        re.findall(
            r"#define ALLOW_(fmi3\w+)\s", (REPO / "fmu_src" / "fmi" / "allowed.h").read_text()
        )
    )
    used = set()
    for path in sorted((REPO / "fmu_src" / "fmi").glob("fmi3*.c")):
        text = re.sub(r"/\*.*?\*/", " ", path.read_text(), flags=re.S)
        used |= set(re.findall(r"FMU_ENTER\(\w+, (fmi3\w+)\)", text))
        for m in re.finditer(r"^fmi3Status\s+(fmi3\w+)\(fmi3Instance\s+(\w+)[^{]*\{", text, re.M):
            body = text[m.end() : text.index("\n}", m.end())]
            assert re.search(
                rf"FMU_ENTER\({m.group(2)}, fmi3\w+\)|return fmi3_refuse\({m.group(2)}", body
            ), f"{path.name}: {m.group(1)}"
    assert used <= table, used - table
    assert len(used) >= 35


def test_illegal_call_names_the_fmi3_state(fmu3_path: Path) -> None:
    """The one call-sequence table answers an FMI 3.0 instance in FMI 3.0's words."""
    md = read_model_description(str(fmu3_path))
    log: list[str] = []
    fmu = FMU3Slave(
        guid=md.guid,
        unzipDirectory=extract(str(fmu3_path)),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="seq",
    )
    fmu.instantiate(logMessage=lambda env, st, cat, msg: log.append(msg.decode()))
    fmu.enterInitializationMode(startTime=0.0)
    fmu.exitInitializationMode()
    with pytest.raises(FMICallException):
        fmu.updateDiscreteStates()  # co-simulation without eventModeUsed: Step Mode
    assert log[-1] == "fmi3UpdateDiscreteStates: illegal call in state StepMode"
    with pytest.raises(FMICallException):
        fmu.enterEventMode()  # state Error now
    assert log[-1] == "fmi3EnterEventMode: illegal call in state Error"
    fmu.freeInstance()


@pytest.mark.parametrize("which", ["plant", "controller"])
def test_every_variable_answers_to_its_value_reference(fmu3_path: Path, which: str) -> None:
    """fmi3Get<type> of every variable of the description after initialisation: the FMU finds
    a value reference by binary search in its generated table, so a row out of order (as
    solver.fast, vr 212, once was after the compliance block) would be "unknown"."""
    path = fmu3_path if which == "plant" else fmu3_path.with_name("DriveController3.fmu")
    md = read_model_description(str(path))
    log: list[str] = []
    fmu = FMU3Slave(
        guid=md.guid,
        unzipDirectory=extract(str(path)),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="all",
    )
    fmu.instantiate(logMessage=lambda env, st, cat, msg: log.append(msg.decode()))
    fmu.enterInitializationMode(startTime=0.0)
    fmu.exitInitializationMode()
    for v in md.modelVariables:
        if v.type == "Clock":  # the controller's input clock: set by the importer, never read
            continue
        n = int(np.prod(v.shape)) if v.dimensions else 1
        got = getattr(fmu, "get" + v.type)([v.valueReference], nValues=n)
        assert len(got) == n, (v.name, log[-1:])
        if v.name == "time":
            assert list(got) == [0.0], (which, got)  # the start time of the experiment
    fmu.terminate()
    fmu.freeInstance()
