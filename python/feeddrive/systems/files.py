"""Write a :class:`~.closed_loop.ClosedLoopSystem` as an SSP 1.0 package, an OSP system
structure and a fmpy container FMU.

- ``<name>.ssp``: ``SystemStructure.ssd`` (two components, their connectors, the two
  connections, a ``DefaultExperiment``), ``resources/<FMU>.fmu`` and one parameter set per
  component, bound to it by a ``ParameterBinding`` with the set inline (libcosim reads
  inline ``ParameterValues`` only, not a ``source``); the same sets as files,
  ``resources/plant.ssv`` and ``resources/controller.ssv``, for tools that take a ``.ssv``.
  The ``DefaultExperiment`` carries two annotations: libcosim's ``osp:FixedStepAlgorithm``
  (base step h, ``numWorkerThreads="0"``: the FMUs step on the calling thread) and
  ``org.feeddrive.delay``, the delay convention the Jacobi files carry (:mod:`.closed_loop`).
- ``<name>_osp/OspSystemStructure.xml`` (libcosim's format, fixed-step algorithm, base step
  Ts/``jacobi_substeps``) next to copies of both FMUs; the start values are ``InitialValues``;
  a comment states the delay convention.
- ``<name>_container.fmu``: fmpy's container FMU (``fmpy.container_fmu``), the two FMUs
  nested, fixed step Ts, the start values as its parameters (``plant.m`` ...), outputs
  ``x`` (plant) and ``u`` (controller).
"""

from __future__ import annotations

import json
import shutil
import tempfile
import zipfile
import zlib
from collections.abc import Sequence
from pathlib import Path
from xml.etree import ElementTree as ET

from fmpy import read_model_description
from fmpy.container_fmu import Configuration
from fmpy.container_fmu.cli import create_container_fmu
from fmpy.container_fmu.config import Component, Connection
from fmpy.model_description import CoSimulation, DefaultExperiment, ModelDescription, ModelVariable

from .closed_loop import CONNECTIONS, ClosedLoopSystem

SSD = "http://ssp-standard.org/SSP1/SystemStructureDescription"
SSC = "http://ssp-standard.org/SSP1/SystemStructureCommon"
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"
OSP = "http://opensimulationplatform.com/MSMI/OSPSystemStructure"
OSP_SSP = "http://opensimulationplatform.com/SSP/OSPAnnotations"
FD = "https://feeddrive.invalid/ssp/delay"
FMU_TYPE = "application/x-fmu-sharedlibrary"
#: the container FMU's configuration, read by its binary at instantiation
CONTAINER_JSON = "resources/container.json"


def _types(fmu: Path) -> dict[str, str]:
    return {v.name: v.type for v in read_model_description(str(fmu), validate=False).modelVariables}


def _literal(kind: str, value: float | int | bool) -> str:
    if kind == "Boolean":
        return "true" if value else "false"
    if kind == "Integer":
        return str(int(value))
    return repr(float(value))


def _typed(system: ClosedLoopSystem, jacobi: bool = True) -> dict[str, list[tuple[str, str, str]]]:
    """component -> [(variable, FMI type, literal)] for a Jacobi engine's file (``jacobi``) or
    the container's; ValueError for a name the FMU lacks."""
    fmus = {"plant": system.plant_fmu, "controller": system.controller_fmu}
    out: dict[str, list[tuple[str, str, str]]] = {}
    for comp, values in system.start_values(jacobi=jacobi).items():
        types = _types(fmus[comp])
        bad = sorted(set(values) - set(types))
        if bad:
            raise ValueError(f"{fmus[comp]}: no variable(s) {bad} (start values of {comp})")
        out[comp] = [(k, types[k], _literal(types[k], v)) for k, v in values.items()]
    return out


def _parameter_set(name: str, values: list[tuple[str, str, str]]) -> ET.Element:
    root = ET.Element(f"{{{SSV}}}ParameterSet", {"version": "1.0", "name": name})
    params = ET.SubElement(root, f"{{{SSV}}}Parameters")
    for var, kind, lit in values:
        p = ET.SubElement(params, f"{{{SSV}}}Parameter", {"name": var})
        ET.SubElement(p, f"{{{SSV}}}{kind}", {"value": lit})
    return root


def _ssv(name: str, values: list[tuple[str, str, str]]) -> bytes:
    return ET.tostring(_parameter_set(name, values), encoding="utf-8", xml_declaration=True)


def _ssd(system: ClosedLoopSystem) -> bytes:
    ET.register_namespace("ssd", SSD)
    ET.register_namespace("ssc", SSC)
    ET.register_namespace("ssv", SSV)
    ET.register_namespace("osp", OSP_SSP)
    ET.register_namespace("fd", FD)
    root = ET.Element(
        f"{{{SSD}}}SystemStructureDescription",
        {"version": "1.0", "name": f"feeddrive_{system.name}"},
    )
    sysel = ET.SubElement(root, f"{{{SSD}}}System", {"name": "closed_loop"})
    elements = ET.SubElement(sysel, f"{{{SSD}}}Elements")
    fmus = {"controller": system.controller_fmu, "plant": system.plant_fmu}
    typed = _typed(system)
    for comp, fmu in fmus.items():
        c = ET.SubElement(
            elements,
            f"{{{SSD}}}Component",
            {"name": comp, "type": FMU_TYPE, "source": f"resources/{fmu.name}"},
        )
        conns = ET.SubElement(c, f"{{{SSD}}}Connectors")
        for a, ac, b, bc in CONNECTIONS:
            if a == comp:
                ET.SubElement(
                    ET.SubElement(conns, f"{{{SSD}}}Connector", {"name": ac, "kind": "output"}),
                    f"{{{SSC}}}Real",
                )
            if b == comp:
                ET.SubElement(
                    ET.SubElement(conns, f"{{{SSD}}}Connector", {"name": bc, "kind": "input"}),
                    f"{{{SSC}}}Real",
                )
        binds = ET.SubElement(c, f"{{{SSD}}}ParameterBindings")
        values = ET.SubElement(
            ET.SubElement(binds, f"{{{SSD}}}ParameterBinding"), f"{{{SSD}}}ParameterValues"
        )
        values.append(_parameter_set(comp, typed[comp]))
    connections = ET.SubElement(sysel, f"{{{SSD}}}Connections")
    for a, ac, b, bc in CONNECTIONS:
        ET.SubElement(
            connections,
            f"{{{SSD}}}Connection",
            {"startElement": a, "startConnector": ac, "endElement": b, "endConnector": bc},
        )
    exp = ET.SubElement(
        root,
        f"{{{SSD}}}DefaultExperiment",
        {"startTime": "0.0", "stopTime": repr(float(system.stop_time))},
    )
    notes = ET.SubElement(exp, f"{{{SSD}}}Annotations")
    # libcosim's fixed-step algorithm stepping the FMUs on the calling thread (no pool wake-up)
    osp = ET.SubElement(
        ET.SubElement(notes, f"{{{SSC}}}Annotation", {"type": "com.opensimulationplatform"}),
        f"{{{OSP_SSP}}}Algorithm",
    )
    ET.SubElement(
        osp,
        f"{{{OSP_SSP}}}FixedStepAlgorithm",
        {"baseStepSize": repr(float(system.jacobi_step)), "numWorkerThreads": "0"},
    )
    conv = ET.SubElement(
        ET.SubElement(notes, f"{{{SSC}}}Annotation", {"type": "org.feeddrive.delay"}),
        f"{{{FD}}}Delay",
    )
    conv.attrib.update(_convention(system))
    return ET.tostring(root, encoding="utf-8", xml_declaration=True)


def _convention(system: ClosedLoopSystem) -> dict[str, str]:
    """The delay convention a Jacobi engine's file carries (see :mod:`.closed_loop`)."""
    return {
        "harnessDelay": str(system.delay) if system.jacobi_substeps == 1 else "none",
        "ctrlDelay": str(system.ctrl_delay(jacobi=True)),
        "macroStep": repr(float(system.jacobi_step)),
        "master": "jacobi",
    }


def _convention_text(system: ClosedLoopSystem) -> str:
    c = _convention(system)
    if c["harnessDelay"] == "none":
        return (
            f" Jacobi master at h = {c['macroStep']} s (Ts/{system.jacobi_substeps}), "
            f"ctrl.delay = {c['ctrlDelay']}: the controller's u lags x by h, a delay the "
            "harness run does not have. "
        )
    return (
        f" Jacobi master at h = Ts = {c['macroStep']} s: the engine's handover is one "
        f"sample of computation delay; ctrl.delay = {c['ctrlDelay']} here reproduces the "
        f"harness run with delay = {c['harnessDelay']}. "
    )


def write_ssp(system: ClosedLoopSystem, path: str | Path) -> Path:
    """Write the SSP 1.0 package ``path`` (``.ssp``)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    typed = _typed(system)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", _ssd(system))
        for comp, values in typed.items():
            z.writestr(f"resources/{comp}.ssv", _ssv(comp, values))
        z.write(system.plant_fmu, f"resources/{system.plant_fmu.name}")
        z.write(system.controller_fmu, f"resources/{system.controller_fmu.name}")
    return path


def osp_structure(
    directory: str | Path,
    step: float,
    simulators: Sequence[tuple[str, Path, list[tuple[str, str, str]]]],
    connections: Sequence[tuple[str, str, str, str]],
    note: str = "",
) -> Path:
    """Write ``directory/OspSystemStructure.xml`` (fixed step ``step`` [s]) with each simulator
    (name, FMU, typed initial values (variable, kind, literal)) and its FMU copied beside it,
    and the connections (simulator, output, simulator, input); returns the XML's path."""
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    ET.register_namespace("", OSP)
    root = ET.Element(f"{{{OSP}}}OspSystemStructure", {"version": "0.1"})
    if note:
        root.append(ET.Comment(note))
    ET.SubElement(root, f"{{{OSP}}}StartTime").text = "0.0"
    ET.SubElement(root, f"{{{OSP}}}BaseStepSize").text = repr(float(step))
    ET.SubElement(root, f"{{{OSP}}}Algorithm").text = "fixedStep"
    sims = ET.SubElement(root, f"{{{OSP}}}Simulators")
    copied: set[Path] = set()
    for name, fmu, values in simulators:
        if fmu not in copied:
            shutil.copyfile(fmu, d / fmu.name)
            copied.add(fmu)
        s = ET.SubElement(
            sims,
            f"{{{OSP}}}Simulator",
            {"name": name, "source": fmu.name, "stepSize": repr(float(step))},
        )
        iv = ET.SubElement(s, f"{{{OSP}}}InitialValues")
        for var, kind, lit in values:
            ET.SubElement(
                ET.SubElement(iv, f"{{{OSP}}}InitialValue", {"variable": var}),
                f"{{{OSP}}}{kind}",
                {"value": lit},
            )
    conns = ET.SubElement(root, f"{{{OSP}}}Connections")
    for a, ac, b, bc in connections:
        vc = ET.SubElement(conns, f"{{{OSP}}}VariableConnection")
        ET.SubElement(vc, f"{{{OSP}}}Variable", {"simulator": a, "name": ac})
        ET.SubElement(vc, f"{{{OSP}}}Variable", {"simulator": b, "name": bc})
    out = d / "OspSystemStructure.xml"
    ET.ElementTree(root).write(out, encoding="utf-8", xml_declaration=True)
    return out


def write_osp(system: ClosedLoopSystem, directory: str | Path) -> Path:
    """Write ``directory/OspSystemStructure.xml`` and the two FMUs beside it; returns the XML."""
    fmus = {"controller": system.controller_fmu, "plant": system.plant_fmu}
    return osp_structure(
        directory,
        system.jacobi_step,
        [(comp, fmus[comp], values) for comp, values in _typed(system).items()],
        CONNECTIONS,
        note=_convention_text(system),
    )


def container_fmu(
    path: str | Path,
    name: str,
    Ts: float,
    stop_time: float,
    fmus: dict[str, Path],
    connections: Sequence[tuple[str, str, str, str]],
    outputs: Sequence[tuple[str, str, str, float | None]],
    values: dict[str, list[tuple[str, str, str]]],
) -> Path:
    """Write fmpy's container FMU ``path`` (FMI 2.0 co-simulation, fixed step ``Ts``): the
    components ``fmus`` (name -> FMU) stepped in order, the ``connections`` (component,
    output, component, input), the container's outputs (its name, component, variable,
    start or None for calculated) and each component's typed start values as parameters
    ``<component>.<variable>`` (those the FMU lets be set: parameters, inputs, exact)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    mds = {c: read_model_description(str(f), validate=False) for c, f in fmus.items()}
    comps = {c: Component(name=c, filename=fmus[c], modelDescription=mds[c]) for c in fmus}
    var = {c: {v.name: v for v in mds[c].modelVariables} for c in fmus}
    md = ModelDescription(
        fmiVersion="2.0",
        modelName=f"feeddrive_{name}",
        instantiationToken="{feedd12c-0000-4000-8000-" + f"{zlib.crc32(name.encode()):012d}" + "}",
        description="feeddrive: " + " + ".join(fmus),
        coSimulation=CoSimulation(modelIdentifier="container_fmu", fixedInternalStepSize=float(Ts)),
        defaultExperiment=DefaultExperiment(
            startTime="0", stopTime=repr(float(stop_time)), stepSize=repr(float(Ts))
        ),
    )
    # fmpy 0.3.32's container binary reserves value reference 0 for the time and maps
    # reference k to the k-th entry of container.json's variables (k >= 1), while
    # create_container_fmu numbers the modelDescription's variables from 0: the variable
    # ``time`` (independent, not in the mappings) takes reference 0 so the two agree
    md.modelVariables.append(
        ModelVariable(name="time", type="Real", causality="independent", variability="continuous")
    )
    entries: list[tuple[ModelVariable, Component, ModelVariable]] = []
    for out, comp, vname, start in outputs:
        entries.append(
            (
                ModelVariable(
                    name=out,
                    type="Real",
                    causality="output",
                    variability="continuous",
                    initial="calculated" if start is None else "exact",
                    start=None if start is None else repr(float(start)),
                ),
                comps[comp],
                var[comp][vname],
            )
        )
    for kind_wanted in ("Real", "Integer", "Boolean"):
        for comp, typed in values.items():
            for vname, kind, lit in typed:
                src = var[comp][vname]
                if kind != kind_wanted or (
                    src.causality not in ("parameter", "input") and src.initial != "exact"
                ):
                    continue
                entries.append(
                    (
                        ModelVariable(
                            name=f"{comp}.{vname}",
                            type=kind,
                            causality="parameter",
                            variability="fixed" if src.variability == "fixed" else "tunable",
                            initial="exact",
                            start=lit,
                        ),
                        comps[comp],
                        src,
                    )
                )
    mappings: dict[ModelVariable, list[tuple[Component, ModelVariable]]] = {}
    for v, comp_obj, src in entries:
        md.modelVariables.append(v)
        mappings[v] = [(comp_obj, src)]

    # fmpy 0.3.32 writes a connection's type as the variable's ("Real"), which its container
    # binary does not parse ("Float64" expected): connect copies typed Float64
    def f64(v: ModelVariable) -> ModelVariable:
        return ModelVariable(
            name=v.name,
            valueReference=v.valueReference,
            type="Float64",
            causality=v.causality,
            variability=v.variability,
        )

    config = Configuration(
        parallelDoStep=False,
        modelDescription=md,
        components=list(comps.values()),
        connections=[
            Connection(
                startElement=comps[a],
                startConnectors=[f64(var[a][ac])],
                endElement=comps[b],
                endConnectors=[f64(var[b][bc])],
            )
            for a, ac, b, bc in connections
        ],
        variableMappings=mappings,
    )
    with tempfile.TemporaryDirectory() as tmp:
        create_container_fmu(config, Path(tmp), path.resolve())
    _compact_container_json(path)
    return path


def _compact_container_json(path: Path) -> None:
    """Rewrite the container FMU's archive for the importer's per-run cost: its
    ``resources/container.json`` without indentation (fmpy 0.3.32's container binary reads
    it one byte per ``read`` call at instantiation: the closed loop's, indented, 66 kB took
    22 ms; compact, 18 kB, 9 ms) and the nested FMUs without their ``sources/`` (no importer
    builds a nested FMU; ``simulate_fmu`` extracts the whole archive on every call)."""
    with zipfile.ZipFile(path) as z:
        entries = [(info, z.read(info)) for info in z.infolist()]
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for info, data in entries:
            parts = info.filename.split("/")
            if len(parts) > 3 and parts[0] == "resources" and parts[2] == "sources":
                continue
            if info.filename == CONTAINER_JSON:
                data = json.dumps(json.loads(data), separators=(",", ":")).encode()
            z.writestr(info, data)


def write_container(system: ClosedLoopSystem, path: str | Path) -> Path:
    """Write the fmpy container FMU ``path`` (FMI 2.0 co-simulation, fixed step Ts): outputs
    ``x`` (plant) and ``u`` (controller), the start values as parameters (``plant.m`` ...)."""
    return container_fmu(
        path,
        system.name,
        system.Ts,
        system.stop_time,
        {"controller": system.controller_fmu, "plant": system.plant_fmu},
        CONNECTIONS,
        [("x", "plant", "x", system.x0), ("u", "controller", "u", None)],
        _typed(system, jacobi=False),
    )


def write_all(system: ClosedLoopSystem, out: str | Path) -> dict[str, Path]:
    """The three forms under ``out``: ``<name>.ssp``, ``<name>_osp/``, ``<name>_container.fmu``."""
    out = Path(out)
    return {
        "ssp": write_ssp(system, out / f"{system.name}.ssp"),
        "osp": write_osp(system, out / f"{system.name}_osp"),
        "container": write_container(system, out / f"{system.name}_container.fmu"),
    }
