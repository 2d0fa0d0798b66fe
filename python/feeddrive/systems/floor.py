"""An engine's own per-step cost: the same engine stepping a trivial pair of FMUs.

Two instances of the controller FMU as a PID with a gain only (a handful of flops per
sample), each one's ``u`` connected to the other's ``x_meas``, at h = Ts, in each engine's
form: OSP structure and SSP package (libcosim), container FMU (fmpy's ``simulate_fmu``),
Ecos's structure.  What an engine spends per macro step on this pair is its floor
(scheduling, the transfer of the connected values, its observers, per-call setup such as
extracting the FMU); the closed loop's time beyond it is the plant's and the controller's.
"""

from __future__ import annotations

import time
import zipfile
from pathlib import Path
from xml.etree import ElementTree as ET

from ..harness.controller_fmu import controller_fmu_parameters, controller_fmu_path
from ..harness.controllers import pid_spec
from .ecos import load_ecospy
from .engines import (
    libcosim_ssp_execution,
    quiet_libcosim,
    simulate_container,
    timed_simulate_until,
)
from .files import (
    FMU_TYPE,
    OSP_SSP,
    SSC,
    SSD,
    SSV,
    _literal,
    _parameter_set,
    _types,
    container_fmu,
    osp_structure,
)

#: the pair's connections (start component, output, end component, input)
PAIR = (("a", "u", "b", "x_meas"), ("b", "u", "a", "x_meas"))


def pair_values(Ts: float = 5e-4) -> dict[str, float | int | bool]:
    """Start values of one instance: a PID with a proportional gain only (Kp = 10 N/m, 0.13
    V/m at the paper's force per volt: the pair's loop gain is below 1), the reference the
    FMU's default input ``x_ref`` (0.15 m)."""
    return {**controller_fmu_parameters(pid_spec(Kp=10.0, Kv=0.0, Ki=0.0), Ts=Ts), "x_meas": 0.0}


def _pair_typed(Ts: float) -> list[tuple[str, str, str]]:
    types = _types(controller_fmu_path())
    return [(k, types[k], _literal(types[k], v)) for k, v in pair_values(Ts).items()]


def write_pair_osp(directory: str | Path, Ts: float = 5e-4) -> Path:
    """The pair as an OSP system structure at h = Ts (the controller FMU copied beside it)."""
    fmu = controller_fmu_path()
    values = _pair_typed(Ts)
    return osp_structure(
        directory,
        Ts,
        [("a", fmu, values), ("b", fmu, values)],
        PAIR,
        note=" A trivial pair of FMUs: the engine's per-step floor. ",
    )


def time_libcosim_pair(directory: str | Path, n: int, Ts: float = 5e-4) -> float:
    """Wall time [s] of libcosim's ``simulate_until(n Ts)`` on the pair (OSP structure)."""
    from libcosimpy.CosimExecution import CosimExecution  # optional: the test extra

    quiet_libcosim()
    osp = write_pair_osp(directory, Ts)
    return timed_simulate_until(CosimExecution.from_osp_config_file(str(osp.parent)), n * Ts)


def time_ecos_pair(n: int, Ts: float = 5e-4) -> float:
    """Wall time [s] of Ecos's ``step_until(n Ts)`` on the pair."""
    ecospy = load_ecospy()
    ss = ecospy.EcosSimulationStructure()
    fmu = str(controller_fmu_path())
    for name in ("a", "b"):
        ss.add_model(name, fmu)
    for a, av, b, bv in PAIR:
        ss.make_real_connection(f"{a}::{av}", f"{b}::{bv}")
    vals = pair_values(Ts)
    ss.add_parameter_set(
        "init",
        {
            f"{c}::{k}": (v if isinstance(v, (bool, int)) else float(v))
            for c in ("a", "b")
            for k, v in vals.items()
        },
    )
    sim = ecospy.EcosSimulation(structure=ss, step_size=Ts)
    try:
        sim.init(parameter_set="init")
        wall0 = time.perf_counter()
        sim.step_until(n * Ts)
        wall = time.perf_counter() - wall0
        sim.terminate()
    finally:
        sim.free()
        ss.free()
    return wall


def write_pair_ssp(path: str | Path, Ts: float = 5e-4) -> Path:
    """The pair as an SSP package for libcosim, its fixed step at h = Ts without worker threads
    (``numWorkerThreads="0"``), each instance's start values as its inline parameter set
    (all of them parameters or inputs, which libcosim's SSP loader binds)."""
    path = Path(path)
    fmu = controller_fmu_path()
    values = _pair_typed(Ts)
    ET.register_namespace("ssd", SSD)
    ET.register_namespace("ssc", SSC)
    ET.register_namespace("ssv", SSV)
    ET.register_namespace("osp", OSP_SSP)
    root = ET.Element(f"{{{SSD}}}SystemStructureDescription", {"version": "1.0", "name": "pair"})
    system = ET.SubElement(root, f"{{{SSD}}}System", {"name": "pair"})
    elements = ET.SubElement(system, f"{{{SSD}}}Elements")
    for name in ("a", "b"):
        c = ET.SubElement(
            elements,
            f"{{{SSD}}}Component",
            {"name": name, "type": FMU_TYPE, "source": f"resources/{fmu.name}"},
        )
        conns = ET.SubElement(c, f"{{{SSD}}}Connectors")
        for var, kind in (("x_meas", "input"), ("u", "output")):
            ET.SubElement(
                ET.SubElement(conns, f"{{{SSD}}}Connector", {"name": var, "kind": kind}),
                f"{{{SSC}}}Real",
            )
        ET.SubElement(
            ET.SubElement(
                ET.SubElement(c, f"{{{SSD}}}ParameterBindings"), f"{{{SSD}}}ParameterBinding"
            ),
            f"{{{SSD}}}ParameterValues",
        ).append(_parameter_set(name, values))
    connections = ET.SubElement(system, f"{{{SSD}}}Connections")
    for a, av, b, bv in PAIR:
        ET.SubElement(
            connections,
            f"{{{SSD}}}Connection",
            {"startElement": a, "startConnector": av, "endElement": b, "endConnector": bv},
        )
    exp = ET.SubElement(root, f"{{{SSD}}}DefaultExperiment", {"startTime": "0.0"})
    alg = ET.SubElement(
        ET.SubElement(
            ET.SubElement(exp, f"{{{SSD}}}Annotations"),
            f"{{{SSC}}}Annotation",
            {"type": "com.opensimulationplatform"},
        ),
        f"{{{OSP_SSP}}}Algorithm",
    )
    ET.SubElement(
        alg,
        f"{{{OSP_SSP}}}FixedStepAlgorithm",
        {"baseStepSize": repr(float(Ts)), "numWorkerThreads": "0"},
    )
    path.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", ET.tostring(root, encoding="utf-8", xml_declaration=True))
        z.write(fmu, f"resources/{fmu.name}")
    return path


def time_libcosim_pair_ssp(directory: str | Path, n: int, Ts: float = 5e-4) -> float:
    """Wall time [s] of libcosim's ``simulate_until(n Ts)`` on the pair's SSP package: the
    fixed step on the calling thread, libcosim's floor without its thread pool."""
    ssp = write_pair_ssp(Path(directory) / "pair.ssp", Ts)
    return timed_simulate_until(libcosim_ssp_execution(ssp), n * Ts)


def write_pair_container(path: str | Path, Ts: float = 5e-4, n: int = 12000) -> Path:
    """The pair as fmpy's container FMU (fixed step Ts), outputs ``a_u`` and ``b_u``: the
    closed loop's container with the plant and the controller replaced by the two gains."""
    fmu = controller_fmu_path()
    values = _pair_typed(Ts)
    return container_fmu(
        path,
        "pair",
        Ts,
        n * Ts,
        {"a": fmu, "b": fmu},
        PAIR,
        [("a_u", "a", "u", None), ("b_u", "b", "u", None)],
        {"a": values, "b": values},
    )


def time_container_pair(directory: str | Path, n: int, Ts: float = 5e-4) -> float:
    """Wall time [s] of fmpy's ``simulate_fmu`` on the pair's container FMU, n steps of Ts,
    two outputs recorded: the same call as the closed loop's (:func:`.engines.run_container`)."""
    fmu = write_pair_container(Path(directory) / "pair_container.fmu", Ts, n)
    return simulate_container(fmu, n, Ts, ("a_u", "b_u"))[1]
