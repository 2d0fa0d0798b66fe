#!/usr/bin/env python3
"""Generate model_vars.h / model_vars.c from modelDescription.xml (the one list of variables).

Usage: gen_vars.py modelDescription.xml OUTDIR

The C code never spells a value reference, a default or a variable name itself: it uses
VR_<name> macros, VRA_<group>[index] arrays and the MODEL_VARS table written here.
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


def main(xml_path: str, outdir: str) -> None:
    root = ET.parse(xml_path).getroot()
    guid = root.get("guid")
    nz = int(root.get("numberOfEventIndicators"))
    svs = root.find("ModelVariables").findall("ScalarVariable")
    rows, defines, groups = [], [], {}
    states = []
    index_of = {}
    for n, sv in enumerate(svs, 1):
        name, vr = sv.get("name"), int(sv.get("valueReference"))
        index_of[n] = vr
        typ_el = sv[0]
        typ = typ_el.tag
        start = typ_el.get("start")
        mn, mx = typ_el.get("min"), typ_el.get("max")
        caus = sv.get("causality", "local")
        var = sv.get("variability", "continuous")
        rows.append((vr, name, typ[0], caus[0] if caus != "calculatedParameter" else "c", var[0],
                     c_double(start, typ) if start is not None else "0.0", 1 if start is not None else 0,
                     c_double(mn, typ) if mn is not None else "-HUGE_VAL",
                     c_double(mx, typ) if mx is not None else "HUGE_VAL",
                     typ_el.get("unit", ""), repr(float(typ_el.get("nominal", "1")))))
        defines.append(f"#define VR_{c_ident(name)} {vr}u")
        m = re.fullmatch(r"(.*)\[(\d+)\]", name)
        if m and not name.startswith("der("):
            groups.setdefault(m.group(1), {})[int(m.group(2))] = vr
    for unk in root.find("ModelStructure").find("Derivatives").findall("Unknown"):
        der_sv = svs[int(unk.get("index")) - 1]
        states.append(index_of[int(der_sv[0].get("derivative"))])
    der_vrs = [int(svs[int(u.get("index")) - 1].get("valueReference"))
               for u in root.find("ModelStructure").find("Derivatives").findall("Unknown")]
    nvr = max(r[0] for r in rows) + 1
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    h = [f"/* Generated from {Path(xml_path).name} by gen_vars.py: do not edit. */",
         "#ifndef MODEL_VARS_H", "#define MODEL_VARS_H", "",
         f'#define MODEL_GUID "{guid}"',
         f"#define MODEL_NVR {nvr}u      /* value references 0..MODEL_NVR-1 */",
         f"#define MODEL_NVARS {len(rows)}",
         f"#define MODEL_NX {len(states)}       /* continuous states */",
         f"#define MODEL_NZ {nz}       /* event indicators */", "",
         "typedef struct {",
         "    unsigned vr; const char *name;",
         "    char type;          /* 'R' Real, 'I' Integer, 'B' Boolean */",
         "    char causality;     /* 'p' parameter, 'i' input, 'o' output, 'l' local */",
         "    char variability;   /* 'f' fixed, 't' tunable, 'd' discrete, 'c' continuous */",
         "    double start; int has_start; double min, max; const char *unit;",
         "    double nominal;     /* the XML's nominal attribute (1 when absent) */",
         "} model_var_t;", "",
         "extern const model_var_t MODEL_VARS[MODEL_NVARS];",
         "extern const short MODEL_VR_INDEX[MODEL_NVR];   /* vr -> row of MODEL_VARS, -1 if none */",
         "extern const unsigned MODEL_STATE_VR[MODEL_NX];  /* continuous states in order */",
         "extern const unsigned MODEL_DER_VR[MODEL_NX];    /* their derivatives */",
         "/* nominal value of continuous state j (from the XML) */",
         "#define MODEL_STATE_NOMINAL(j) (MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].nominal)", ""]
    h += defines
    h.append("")
    for g, members in groups.items():
        size = max(members) + 1
        arr = ", ".join(str(members.get(k, 0xFFFFFFFF)) + "u" for k in range(size))
        h.append(f"static const unsigned VRA_{c_ident(g)}[{size}] = {{{arr}}};  /* {g}[k] */")
    h += ["", "#endif", ""]
    (out / "model_vars.h").write_text("\n".join(h))
    idx = [-1] * nvr
    for n, r in enumerate(rows):
        idx[r[0]] = n
    c = [f"/* Generated from {Path(xml_path).name} by gen_vars.py: do not edit. */",
         "#include <math.h>", '#include "model_vars.h"', "",
         "const model_var_t MODEL_VARS[MODEL_NVARS] = {"]
    for r in rows:
        c.append(f'    {{{r[0]}u, "{r[1]}", \'{r[2]}\', \'{r[3]}\', \'{r[4]}\', {r[5]}, {r[6]}, {r[7]}, {r[8]}, "{r[9]}", {r[10]}}},')
    c += ["};", "", "const short MODEL_VR_INDEX[MODEL_NVR] = {" + ", ".join(map(str, idx)) + "};",
          "const unsigned MODEL_STATE_VR[MODEL_NX] = {" + ", ".join(f"{v}u" for v in states) + "};",
          "const unsigned MODEL_DER_VR[MODEL_NX] = {" + ", ".join(f"{v}u" for v in der_vrs) + "};", ""]
    (out / "model_vars.c").write_text("\n".join(c))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
