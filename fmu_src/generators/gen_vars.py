#!/usr/bin/env python3
"""Generate model_vars.h / model_vars.c from modelDescription.xml (the one list of variables).

Usage: gen_vars.py modelDescription.xml OUTDIR
       gen_vars.py --prefix CTRL [--import PLANT_XML PREFIX OFFSET] modelDescription.xml OUTDIR

The C code never spells a value reference, a default or a variable name itself: it uses
VR_<name> macros, VRA_<group>[index] arrays and the MODEL_VARS table written here.  The plant's
effects are its ``effects.<id>`` switches: model_effects.h lists them, in the XML's order, as the
X-macro MODEL_EFFECTS(X) = X(<id>) ..., from which physics/effects.c builds the effect table of
``&effect_<id>`` entries (each defined in the effect's own C file).

With ``--prefix CTRL`` (the controller FMU) the files are ctrl_vars.h/.c and the names
CVR_<name>, CVRA_<group>, CVRA2_<group>[i][j] (names like ``ss.Ac[1,2]``), CTRL_VARS, ...,
so that they can live in one library next to the plant's.  ``--import`` appends every
parameter of another model description (the plant's) under PREFIX with value reference
OFFSET + its own, and writes the merged OUTDIR/modelDescription.xml: the plant's parameters
keep the plant's XML as their one source of truth.
"""

from __future__ import annotations

import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path


def c_ident(name: str) -> str:
    """friction.F[1] -> friction_F_1, der(friction.F[1]) -> der_friction_F_1."""
    return re.sub(r"_+", "_", re.sub(r"[^A-Za-z0-9]", "_", name)).strip("_")


def c_double(text: str, typ: str) -> str:
    if typ == "Boolean":
        return "1.0" if text == "true" else "0.0"
    return repr(float(text))


#: the fields every variable table has (the plant's adds the nominal value)
VAR_FIELDS = [
    "    unsigned vr; const char *name;",
    "    char type;          /* 'R' Real, 'I' Integer, 'B' Boolean */",
    "    char causality;     /* 'p' parameter, 'i' input, 'o' output, 'l' local */",
    "    char variability;   /* 'f' fixed, 't' tunable, 'd' discrete, 'c' continuous */",
    "    double start; int has_start; double min, max; const char *unit;",
]


def var_row(sv: ET.Element) -> tuple:
    """(vr, name, type, causality, variability, start, has_start, min, max, unit) of a variable."""
    t = sv[0]
    start, mn, mx = t.get("start"), t.get("min"), t.get("max")
    caus = sv.get("causality", "local")
    return (
        int(sv.get("valueReference")),
        sv.get("name"),
        t.tag[0],
        caus[0] if caus != "calculatedParameter" else "c",
        sv.get("variability", "continuous")[0],
        c_double(start, t.tag) if start is not None else "0.0",
        1 if start is not None else 0,
        c_double(mn, t.tag) if mn is not None else "-HUGE_VAL",
        c_double(mx, t.tag) if mx is not None else "HUGE_VAL",
        t.get("unit", ""),
    )


def group_arrays(groups: dict[str, dict[int, int]], prefix: str) -> list[str]:
    """One C array per group of indexed variables name[k]: the value reference of each k."""
    lines = []
    for g, members in groups.items():
        size = max(members) + 1
        arr = ", ".join(str(members.get(k, 0xFFFFFFFF)) + "u" for k in range(size))
        lines.append(
            f"static const unsigned {prefix}_{c_ident(g)}[{size}] = {{{arr}}};  /* {g}[k] */"
        )
    return lines


def vr_index(rows: list[tuple], nvr: int) -> str:
    """The initialiser of the vr -> row table (-1 where a value reference is unused)."""
    idx = [-1] * nvr
    for n, r in enumerate(rows):
        idx[r[0]] = n
    return ", ".join(map(str, idx))


def table_rows(rows: list[tuple]) -> list[str]:
    """The initialiser lines of a variable table, one per row (all of each row's fields)."""
    out = []
    for r in rows:
        fields = [
            f"{r[0]}u",
            f'"{r[1]}"',
            f"'{r[2]}'",
            f"'{r[3]}'",
            f"'{r[4]}'",
            *map(str, r[5:9]),
            f'"{r[9]}"',
        ]
        out.append("    {" + ", ".join(fields + [str(f) for f in r[10:]]) + "},")
    return out


def import_parameters(root: ET.Element, other_xml: str, prefix: str, offset: int) -> None:
    """Append ``other_xml``'s parameters to ``root``'s ModelVariables, renamed and shifted."""
    mv = root.find("ModelVariables")
    for sv in ET.parse(other_xml).getroot().find("ModelVariables").findall("ScalarVariable"):
        if sv.get("causality") != "parameter":
            continue
        sv.set("name", prefix + sv.get("name"))
        sv.set("valueReference", str(offset + int(sv.get("valueReference"))))
        sv.set("description", "Nominal plant (feedforward): " + sv.get("description", ""))
        mv.append(sv)


def main(
    xml_path: str, outdir: str, prefix: str = "MODEL", imports: tuple[str, str, int] | None = None
) -> None:
    tree = ET.parse(xml_path)
    root = tree.getroot()
    if imports is not None:
        import_parameters(root, *imports)
        Path(outdir).mkdir(parents=True, exist_ok=True)
        ET.indent(tree)
        tree.write(Path(outdir) / "modelDescription.xml", encoding="UTF-8", xml_declaration=True)
    if prefix != "MODEL":
        _write(root, Path(xml_path).name, outdir, prefix)
        return
    guid = root.get("guid")
    nz = int(root.get("numberOfEventIndicators"))
    svs = root.find("ModelVariables").findall("ScalarVariable")
    rows, defines, groups = [], [], {}
    states = []
    index_of = {}
    for n, sv in enumerate(svs, 1):
        name, vr = sv.get("name"), int(sv.get("valueReference"))
        index_of[n] = vr
        rows.append((*var_row(sv), repr(float(sv[0].get("nominal", "1")))))
        defines.append(f"#define VR_{c_ident(name)} {vr}u")
        m = re.fullmatch(r"(.*)\[(\d+)\]", name)
        if m and not name.startswith("der("):
            groups.setdefault(m.group(1), {})[int(m.group(2))] = vr
    for unk in root.find("ModelStructure").find("Derivatives").findall("Unknown"):
        der_sv = svs[int(unk.get("index")) - 1]
        states.append(index_of[int(der_sv[0].get("derivative"))])
    der_vrs = [
        int(svs[int(u.get("index")) - 1].get("valueReference"))
        for u in root.find("ModelStructure").find("Derivatives").findall("Unknown")
    ]
    nvr = max(r[0] for r in rows) + 1
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    h = [
        f"/* Generated from {Path(xml_path).name} by gen_vars.py: do not edit. */",
        "#ifndef MODEL_VARS_H",
        "#define MODEL_VARS_H",
        "",
        f'#define MODEL_GUID "{guid}"',
        f"#define MODEL_NVR {nvr}u      /* value references 0..MODEL_NVR-1 */",
        f"#define MODEL_NVARS {len(rows)}",
        f"#define MODEL_NX {len(states)}       /* continuous states */",
        f"#define MODEL_NZ {nz}       /* event indicators */",
        "",
        "typedef struct {",
        *VAR_FIELDS,
        "    double nominal;     /* the XML's nominal attribute (1 when absent) */",
        "} model_var_t;",
        "",
        "extern const model_var_t MODEL_VARS[MODEL_NVARS];",
        "extern const short MODEL_VR_INDEX[MODEL_NVR];   /* vr -> row of MODEL_VARS, -1 if none */",
        "extern const unsigned MODEL_STATE_VR[MODEL_NX];  /* continuous states in order */",
        "extern const unsigned MODEL_DER_VR[MODEL_NX];    /* their derivatives */",
        "/* nominal value of continuous state j (from the XML) */",
        "#define MODEL_STATE_NOMINAL(j) (MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].nominal)",
        "",
    ]
    h += defines
    h.append("")
    h += group_arrays(groups, "VRA")
    h += ["", "#endif", ""]
    (out / "model_vars.h").write_text("\n".join(h))
    c = [
        f"/* Generated from {Path(xml_path).name} by gen_vars.py: do not edit. */",
        "#include <math.h>",
        '#include "model_vars.h"',
        "",
        "const model_var_t MODEL_VARS[MODEL_NVARS] = {",
    ]
    c += table_rows(rows)
    c += [
        "};",
        "",
        "const short MODEL_VR_INDEX[MODEL_NVR] = {" + vr_index(rows, nvr) + "};",
        "const unsigned MODEL_STATE_VR[MODEL_NX] = {" + ", ".join(f"{v}u" for v in states) + "};",
        "const unsigned MODEL_DER_VR[MODEL_NX] = {" + ", ".join(f"{v}u" for v in der_vrs) + "};",
        "",
    ]
    (out / "model_vars.c").write_text("\n".join(c))
    _write_effects([r[1] for r in rows], Path(xml_path).name, out)


def effect_ids(names: list[str]) -> list[str]:
    """The ids of the effect switches ``effects.<id>``, in the order of ``names``."""
    return [n.split(".", 1)[1] for n in names if re.fullmatch(r"effects\.[a-z][a-z0-9_]*", n)]


def _write_effects(names: list[str], src: str, out: Path) -> None:
    """model_effects.h: MODEL_NEFFECTS and the X-macro MODEL_EFFECTS(X) of the effect ids."""
    ids = effect_ids(names)
    h = [
        f"/* Generated from {src} by gen_vars.py: do not edit. */",
        "#ifndef MODEL_EFFECTS_H",
        "#define MODEL_EFFECTS_H",
        "",
        f"#define MODEL_NEFFECTS {len(ids)}",
        "/* X(id) for every effect switch effects.<id>, in the XML's order */",
        "#define MODEL_EFFECTS(X) \\",
    ]
    h += [f"    X({i}) \\" for i in ids]
    h += ["", "#endif", ""]
    (out / "model_effects.h").write_text("\n".join(h))


def _write(root: ET.Element, src: str, outdir: str, prefix: str) -> None:
    """The prefixed table of an FMU without continuous states (the controller's)."""
    svs = root.find("ModelVariables").findall("ScalarVariable")
    low, vrp = prefix.lower(), "C" + "VR"
    rows, defines, groups, groups2 = [], [], {}, {}
    for sv in svs:
        name, vr = sv.get("name"), int(sv.get("valueReference"))
        rows.append(var_row(sv))
        defines.append(f"#define {vrp}_{c_ident(name)} {vr}u")
        m1 = re.fullmatch(r"(.*)\[(\d+)\]", name)
        m2 = re.fullmatch(r"(.*)\[(\d+),(\d+)\]", name)
        if m1:
            groups.setdefault(m1.group(1), {})[int(m1.group(2))] = vr
        elif m2:
            groups2.setdefault(m2.group(1), {})[(int(m2.group(2)), int(m2.group(3)))] = vr
    nvr = max(r[0] for r in rows) + 1
    P = prefix
    h = [
        f"/* Generated from {src} by gen_vars.py: do not edit. */",
        f"#ifndef {P}_VARS_H",
        f"#define {P}_VARS_H",
        "",
        f'#define {P}_GUID "{root.get("guid")}"',
        f"#define {P}_NVR {nvr}u      /* value references 0..{P}_NVR-1 */",
        f"#define {P}_NVARS {len(rows)}",
        "",
        "typedef struct {",
        *VAR_FIELDS,
        f"}} {low}_var_t;",
        "",
        f"extern const {low}_var_t {P}_VARS[{P}_NVARS];",
        f"extern const short {P}_VR_INDEX[{P}_NVR];   /* vr -> row of {P}_VARS, -1 if none */",
        "",
    ]
    h += defines
    h.append("")
    h += group_arrays(groups, vrp + "A")
    for g, members in groups2.items():
        ni = max(i for i, _ in members) + 1
        nj = max(j for _, j in members) + 1
        arr = ", ".join(
            "{" + ", ".join(str(members.get((i, j), 0xFFFFFFFF)) + "u" for j in range(nj)) + "}"
            for i in range(ni)
        )
        h.append(
            f"static const unsigned {vrp}A2_{c_ident(g)}[{ni}][{nj}] = {{{arr}}};  /* {g}[i,j] */"
        )
    h += ["", "#endif", ""]
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{low}_vars.h").write_text("\n".join(h))
    c = [
        f"/* Generated from {src} by gen_vars.py: do not edit. */",
        "#include <math.h>",
        f'#include "{low}_vars.h"',
        "",
        f"const {low}_var_t {P}_VARS[{P}_NVARS] = {{",
    ]
    c += table_rows(rows)
    c += ["};", "", f"const short {P}_VR_INDEX[{P}_NVR] = {{" + vr_index(rows, nvr) + "};", ""]
    (out / f"{low}_vars.c").write_text("\n".join(c))


if __name__ == "__main__":
    args = sys.argv[1:]
    pre, imp = "MODEL", None
    if args[:1] == ["--prefix"]:
        pre, args = args[1], args[2:]
    if args[:1] == ["--import"]:
        imp, args = (args[1], args[2], int(args[3])), args[4:]
    main(args[0], args[1], pre, imp)
