#!/usr/bin/env python3
"""Generate the FMI 3.0 model description and its value table from the FMI 2.0 one.

Usage: gen_fmi3.py modelDescription.xml OUTDIR
       gen_fmi3.py --controller build/gen/controller/modelDescription.xml OUTDIR

(``--controller``: the controller FMU's merged FMI 2.0 description, co-simulation only, no
arrays; its FMI 3.0 glue is the plant's (fmu_src/fmi/fmi3.c) with its clock
(controller/ctrl_clock.c). It adds the input clock
``tick``: periodic, its interval the parameter Ts (``intervalVariability="fixed"``), the inputs
and outputs clocked by it (``clocks``), and Event Mode (``hasEventMode``): an importer that
instantiates with eventModeUsed gives every sample as a tick in Event Mode.)

modelDescription.xml (FMI 2.0) stays the one list of variables. From it this writes
OUTDIR/modelDescription.xml (FMI 3.0), OUTDIR/buildDescription.xml (for sources/) and
OUTDIR/model_vars3.h/.c (the FMI 3.0 value references of the glue, fmu_src/fmi/fmi3_view.c):

- every scalar keeps its name, value reference, unit, start, min, max and nominal; Real becomes
  Float64, Integer Int32, Boolean Boolean;
- the per-element groups ``friction.F[k]``, ``der(friction.F[k])``, ``friction.nu[k]``,
  ``friction.k[k]`` and ``friction.stuck[k]`` (k = 1..10) become one array each, named without
  the index, with the value reference of element 1 and a ``Dimension`` given by the structural
  parameter ``friction.N`` (causality ``structuralParameter``, set in Configuration Mode);
- ``time`` (value reference 0) is the independent variable, ``eventIndicators`` (an FMI 3.0
  variable, the FMI 2.0 ``numberOfEventIndicators`` long) carries the event indicators;
- ``derivative`` points to a value reference, the ModelStructure lists value references.
"""

from __future__ import annotations

import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

N_NAME = "friction.N"
N_ARRAYS = ("friction.F", "der(friction.F)", "friction.nu", "friction.k", "friction.stuck")
TYPES = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean"}
VR_TIME, VR_INDICATORS = 0, 80
CTRL_VR_TICK = 9  # the controller's input clock (controller/ctrl_clock.c's VR_TICK)


def array_of(name: str) -> tuple[str, int] | None:
    """``friction.F[3]`` -> ("friction.F", 3); ``der(friction.F[3])`` -> ("der(friction.F)", 3)."""
    m = re.fullmatch(r"der\((.*)\[(\d+)\]\)", name)
    if m and f"der({m.group(1)})" in N_ARRAYS:
        return f"der({m.group(1)})", int(m.group(2))
    m = re.fullmatch(r"(.*)\[(\d+)\]", name)
    if m and m.group(1) in N_ARRAYS:
        return m.group(1), int(m.group(2))
    return None


def fmi3_variables(root2: ET.Element) -> list[dict]:
    """The FMI 3.0 variables in FMI 2.0 order: dicts with name, vr, type, attrs, elems (FMI 2.0
    value references of the elements), dim (True: of dimension friction.N), derivative_of (the FMI
    2.0 index of the state)."""
    svs = root2.find("ModelVariables").findall("ScalarVariable")
    n_sv = [sv for sv in svs if sv.get("name") == N_NAME]
    n_vr = int(n_sv[0].get("valueReference")) if n_sv else -1
    n_start = int(n_sv[0][0].get("start")) if n_sv else 0
    out: list[dict] = [
        {
            "name": "time",
            "vr": VR_TIME,
            "type": "Float64",
            "elems": [],
            "dim": False,
            "attrs": {
                "causality": "independent",
                "variability": "continuous",
                "description": "Simulation time",
            },
            "typed": {"unit": "s"},
        }
    ]
    by_name: dict[str, dict] = {}
    for idx, sv in enumerate(svs, 1):
        t = sv[0]
        arr = array_of(sv.get("name"))
        if arr is not None and arr[0] in by_name:
            v = by_name[arr[0]]
            v["elems"].append(int(sv.get("valueReference")))
            v["starts"].append(t.get("start"))
            continue
        attrs = {
            k: sv.get(k) for k in ("causality", "variability", "initial") if sv.get(k) is not None
        }
        attrs["description"] = sv.get("description", "")
        if sv.get("name") == N_NAME:
            attrs["causality"] = "structuralParameter"
        typed = {k: t.get(k) for k in ("unit", "nominal", "min", "max") if t.get(k) is not None}
        v = {
            "name": arr[0] if arr else sv.get("name"),
            "vr": int(sv.get("valueReference")),
            "type": TYPES[t.tag],
            "attrs": attrs,
            "typed": typed,
            "elems": [int(sv.get("valueReference"))],
            "starts": [t.get("start")],
            "dim": arr is not None,
            "index2": idx,
            "derivative_of": int(t.get("derivative")) if t.get("derivative") else None,
        }
        if arr is not None:
            assert arr[1] == 1, sv.get("name")
            v["attrs"]["description"] = re.sub(
                r"_1\b",
                "_k",
                re.sub(r"\belement 1\b", "element k (k = 1..N)", v["attrs"]["description"]),
            )
            by_name[arr[0]] = v
        out.append(v)
    index_vr = {v["index2"]: v["vr"] for v in out if "index2" in v}
    for v in out:
        if v.get("derivative_of"):
            v["typed"]["derivative"] = str(index_vr[v["derivative_of"]])
        if v["dim"]:
            assert len(v["elems"]) == 10, v["name"]
            v["dim_vr"] = n_vr
            starts = v["starts"][:n_start]
            if all(s is not None for s in starts):
                v["typed"]["start"] = " ".join(fmt_start(s, v["type"]) for s in starts)
        elif v["name"] != "time" and v["starts"][0] is not None:
            v["typed"]["start"] = fmt_start(v["starts"][0], v["type"])
    nz = int(root2.get("numberOfEventIndicators", "0"))
    if nz == 0:
        return out
    out.append(
        {
            "name": "eventIndicators",
            "vr": VR_INDICATORS,
            "type": "Float64",
            "elems": [],
            "dim": False,
            "nz": nz,
            "attrs": {
                "causality": "local",
                "variability": "continuous",
                "initial": "calculated",
                "description": "Event indicators (friction switches: an element's stick/slip "
                "condition, or the static model's)",
            },
            "typed": {},
        }
    )
    return out


def fmt_start(s: str, typ: str) -> str:
    if typ == "Boolean":
        return s
    return s


def structure(root2: ET.Element, vars3: list[dict]) -> ET.Element:
    svs = root2.find("ModelVariables").findall("ScalarVariable")
    idx2vr: dict[int, int] = {}
    for v in vars3:
        for e in v["elems"]:
            idx2vr[next(i for i, sv in enumerate(svs, 1) if int(sv.get("valueReference")) == e)] = (
                v["vr"]
            )
    ms2 = root2.find("ModelStructure")
    ms = ET.Element("ModelStructure")

    def unique(element: str) -> list[int]:
        seen: list[int] = []
        for u in ms2.find(element).findall("Unknown") if ms2.find(element) is not None else []:
            vr = idx2vr[int(u.get("index"))]
            if vr not in seen:
                seen.append(vr)
        return seen

    for vr in unique("Outputs"):
        ET.SubElement(ms, "Output", valueReference=str(vr))
    for vr in unique("Derivatives"):
        ET.SubElement(ms, "ContinuousStateDerivative", valueReference=str(vr))
    clocked = {
        v["vr"] for v in vars3 if "clocks" in v["typed"]
    }  # computed at the ticks, not initially
    for vr in unique("InitialUnknowns"):
        if vr not in clocked:
            ET.SubElement(ms, "InitialUnknown", valueReference=str(vr))
    if any(v["name"] == "eventIndicators" for v in vars3):
        ET.SubElement(ms, "EventIndicator", valueReference=str(VR_INDICATORS))
    return ms


def clock_controller(vars3: list[dict]) -> list[dict]:
    """The controller's variables with the input clock ``tick`` (after ``time``) and its inputs
    and outputs clocked by it (discrete: they change at the ticks only)."""
    names = {v["name"]: v for v in vars3}
    assert "Ts" in names and CTRL_VR_TICK not in {v["vr"] for v in vars3}
    out = [
        vars3[0],
        {
            "name": "tick",
            "vr": CTRL_VR_TICK,
            "type": "Clock",
            "elems": [],
            "dim": False,
            "attrs": {
                "causality": "input",
                "variability": "discrete",
                "description": "Sample clock: ticks at t0 + k Ts (interval the parameter Ts); "
                "with Event Mode every sample is taken at a tick",
            },
            "typed": {"intervalVariability": "fixed"},
        },
    ]
    for v in vars3[1:]:
        if v["attrs"].get("causality") in ("input", "output"):
            v["attrs"]["variability"] = "discrete"
            v["typed"]["clocks"] = str(CTRL_VR_TICK)
        out.append(v)
    return out


def model_description(root2: ET.Element, vars3: list[dict]) -> ET.ElementTree:
    r = ET.Element(
        "fmiModelDescription",
        {
            "fmiVersion": "3.0",
            "modelName": root2.get("modelName"),
            "instantiationToken": root2.get("guid"),
            "description": root2.get("description"),
            "generationTool": root2.get("generationTool")
            + " (gen_fmi3.py from the FMI 2.0 description)",
            "version": root2.get("version"),
            "variableNamingConvention": "structured",
        },
    )
    cs2 = root2.find("CoSimulation")
    state = cs2.get("canGetAndSetFMUstate", "false")
    common = {
        "modelIdentifier": identifier(root2),
        "canGetAndSetFMUState": state,
        "canSerializeFMUState": cs2.get("canSerializeFMUstate", "false"),
    }
    if root2.find("ModelExchange") is not None:
        ET.SubElement(r, "ModelExchange", {**common, "needsCompletedIntegratorStep": "false"})
    # the plant: friction switches; the controller: its clock
    events = (
        "true"
        if root2.find("ModelExchange") is not None or any(v["type"] == "Clock" for v in vars3)
        else "false"
    )
    early = "true" if root2.find("ModelExchange") is not None else "false"
    ET.SubElement(
        r,
        "CoSimulation",
        {
            **common,
            "canHandleVariableCommunicationStepSize": "true",
            **(
                {"maxOutputDerivativeOrder": cs2.get("maxOutputDerivativeOrder")}
                if cs2.get("maxOutputDerivativeOrder")
                else {}
            ),
            "hasEventMode": events,
            "mightReturnEarlyFromDoStep": early,
            "providesIntermediateUpdate": "false",
        },
    )
    for element in ("UnitDefinitions", "LogCategories", "DefaultExperiment"):
        if root2.find(element) is not None:
            r.append(root2.find(element))
    mv = ET.SubElement(r, "ModelVariables")
    for v in vars3:
        e = ET.SubElement(
            mv,
            v["type"],
            {"name": v["name"], "valueReference": str(v["vr"]), **v["attrs"], **v["typed"]},
        )
        if v["dim"]:
            ET.SubElement(e, "Dimension", valueReference=str(v["dim_vr"]))
        if "nz" in v:
            ET.SubElement(e, "Dimension", start=str(v["nz"]))
    r.append(structure(root2, vars3))
    tree = ET.ElementTree(r)
    ET.indent(tree)
    return tree


def c_table(vars3: list[dict], src: str) -> tuple[str, str]:
    rows, elems = [], []
    for v in vars3:
        first = len(elems)
        elems += v["elems"]
        kind = 0 if v["name"] == "time" else (2 if "nz" in v else (1 if v["dim"] else 3))
        rows.append(
            (
                v["vr"],
                v["name"],
                v["type"][0] if v["type"] != "Float64" else "R",
                first,
                len(v["elems"]) if v["elems"] else v.get("nz", 1),
                kind,
            )
        )
    rows.sort(key=lambda r: r[0])  # fmi3_view.c finds a row by binary search on the vr
    h = [
        f"/* Generated from {src} by gen_fmi3.py: do not edit. */",
        "#ifndef MODEL_VARS3_H",
        "#define MODEL_VARS3_H",
        "",
        f"#define MODEL3_NVARS {len(rows)}",
        f"#define MODEL3_NELEMS {len(elems)}",
        f"#define VR3_time {VR_TIME}u",
        f"#define VR3_eventIndicators {VR_INDICATORS}u",
        "",
        "/* kind: 0 the independent time, 1 an array of dimension friction.N, 2 the event indicators,",
        " * 3 a scalar (the FMI 2.0 variable of the same value reference) */",
        "typedef struct { unsigned vr; const char *name; char type; int first, count, kind; } model_var3_t;",
        "",
        "extern const model_var3_t MODEL3_VARS[MODEL3_NVARS];",
        "extern const unsigned MODEL3_ELEMS[MODEL3_NELEMS];  /* FMI 2.0 value references of the elements */",
        "",
        "#endif",
        "",
    ]
    c = [
        f"/* Generated from {src} by gen_fmi3.py: do not edit. */",
        '#include "model_vars3.h"',
        "",
        "const model_var3_t MODEL3_VARS[MODEL3_NVARS] = {",
    ]
    c += [f"    {{{r[0]}u, \"{r[1]}\", '{r[2]}', {r[3]}, {r[4]}, {r[5]}}}," for r in rows]
    c += [
        "};",
        "",
        "const unsigned MODEL3_ELEMS[MODEL3_NELEMS] = {" + ", ".join(f"{e}u" for e in elems) + "};",
        "",
    ]
    return "\n".join(h), "\n".join(c)


def identifier(root2: ET.Element) -> str:
    """The FMI 3.0 model identifier: the FMI 2.0 one + "3" (LinearMotorFeedDrive3, DriveController3)."""
    return root2.find("CoSimulation").get("modelIdentifier") + "3"


def build_description(root2: ET.Element, glue: list[str]) -> ET.ElementTree:
    """sources/buildDescription.xml: the FMI 2.0 source files and the FMI 3.0 glue ``glue``."""
    names = [
        f.get("name") for f in root2.find("CoSimulation").find("SourceFiles").findall("File")
    ] + glue
    r = ET.Element("fmiBuildDescription", fmiVersion="3.0")
    bc = ET.SubElement(r, "BuildConfiguration", modelIdentifier=identifier(root2))
    fs = ET.SubElement(bc, "SourceFileSet", language="C99")
    for n in names:
        ET.SubElement(fs, "SourceFile", name=n)
    ET.SubElement(fs, "PreprocessorDefinition", name="_POSIX_C_SOURCE", value="200809L")
    ET.SubElement(fs, "PreprocessorDefinition", name="_DEFAULT_SOURCE")
    tree = ET.ElementTree(r)
    ET.indent(tree)
    return tree


def main(xml_path: str, outdir: str, controller: bool = False) -> None:
    root2 = ET.parse(xml_path).getroot()
    vars3 = fmi3_variables(root2)
    if controller:
        vars3 = clock_controller(vars3)
    vrs = [v["vr"] for v in vars3]
    assert len(set(vrs)) == len(vrs), "duplicate FMI 3.0 value reference"
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    model_description(root2, vars3).write(
        out / "modelDescription.xml", encoding="UTF-8", xml_declaration=True
    )
    fmi_glue = Path(__file__).resolve().parents[1] / "fmi"
    glue = (
        sorted(p.name for p in fmi_glue.glob("fmi3*.c"))
        + (["ctrl_clock.c"] if controller else [])
        + ["model_vars3.c"]
    )
    build_description(root2, glue).write(
        out / "buildDescription.xml", encoding="UTF-8", xml_declaration=True
    )
    h, c = c_table(vars3, Path(xml_path).name)
    (out / "model_vars3.h").write_text(h)
    (out / "model_vars3.c").write_text(c)


if __name__ == "__main__":
    args = sys.argv[1:]
    ctrl = args[:1] == ["--controller"]
    main(*(args[1:] if ctrl else args), controller=ctrl)
