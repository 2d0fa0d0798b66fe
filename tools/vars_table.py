#!/usr/bin/env python3
"""Print the Markdown tables of the FMU's variables (for docs/variables.md): the FMI 2.0 one from
modelDescription.xml, and the FMI 3.0 variables that differ from it (arrays of dimension
friction.N, the structural parameter, time, eventIndicators), from the FMI 3.0 description
fmu_src/gen_fmi3.py derives from the same file.

Usage: vars_table.py [modelDescription.xml]   — or --check docs/variables.md to verify both are current,
       --update docs/variables.md to rewrite them.
"""
from __future__ import annotations

import importlib.util
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BLOCKS = {"fmi2": ("<!-- variables:begin -->", "<!-- variables:end -->"),
          "fmi3": ("<!-- variables3:begin -->", "<!-- variables3:end -->")}


def table(xml_path: Path) -> str:
    root = ET.parse(xml_path).getroot()
    rows = ["| name | causality | variability | type | unit | default | description |",
            "|---|---|---|---|---|---|---|"]
    for sv in root.find("ModelVariables").findall("ScalarVariable"):
        t = sv[0]
        desc = sv.get("description", "").replace("|", "/")
        rows.append(f"| `{sv.get('name')}` | {sv.get('causality', 'local')} | {sv.get('variability', 'continuous')} "
                    f"| {t.tag} | {t.get('unit', '')} | {t.get('start', '')} | {desc} |")
    return "\n".join(rows)


def _gen_fmi3():
    spec = importlib.util.spec_from_file_location("gen_fmi3", ROOT / "fmu_src" / "gen_fmi3.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def table3(xml_path: Path) -> str:
    """The FMI 3.0 variables that are not an FMI 2.0 scalar of the same name."""
    gen = _gen_fmi3()
    rows = ["| name | value reference | causality | type | dimension | unit | default | FMI 2.0 |",
            "|---|---|---|---|---|---|---|---|"]
    for v in gen.fmi3_variables(ET.parse(xml_path).getroot()):
        changed = v["name"] in ("time", "eventIndicators") or v["dim"] or v["attrs"]["causality"] == "structuralParameter"
        if not changed:
            continue
        dim = "friction.N" if v["dim"] else (str(v["nz"]) if "nz" in v else "")
        e = v["elems"]
        if v["dim"]:
            elem = f"der(friction.F[k])" if v["name"].startswith("der(") else f"{v['name']}[k]"
            step = ", ..., " if e[1] - e[0] > 1 else ".."
            was = f"`{elem}`, k = 1..10 (value references {e[0]}{', ' + str(e[1]) if step != '..' else ''}{step}{e[-1]})"
        else:
            was = {"time": "— (independent variable)", "eventIndicators": "`numberOfEventIndicators`"}.get(
                v["name"], f"`{v['name']}` (parameter)")
        rows.append(f"| `{v['name']}` | {v['vr']} | {v['attrs']['causality']} | {v['type']} | {dim} "
                    f"| {v['typed'].get('unit', '')} | {v['typed'].get('start', '')} | {was} |")
    return "\n".join(rows)


def _current(text: str, key: str, body: str) -> bool:
    begin, end = BLOCKS[key]
    m = re.search(re.escape(begin) + r"(.*?)" + re.escape(end), text, re.S)
    return bool(m) and m.group(1).strip() == body.strip()


def main() -> int:
    xml = ROOT / "modelDescription.xml"
    bodies = {"fmi2": table(xml), "fmi3": table3(xml)}
    if len(sys.argv) == 3 and sys.argv[1] == "--check":
        text = Path(sys.argv[2]).read_text()
        if not all(_current(text, k, b) for k, b in bodies.items()):
            print(f"{sys.argv[2]}: the variables table is not current; run tools/vars_table.py --update docs/variables.md")
            return 1
        return 0
    if len(sys.argv) == 3 and sys.argv[1] == "--update":
        p = Path(sys.argv[2])
        text = p.read_text()
        for key, body in bodies.items():
            begin, end = BLOCKS[key]
            text = re.sub(re.escape(begin) + r".*?" + re.escape(end),
                          lambda _: begin + "\n" + body + "\n" + end, text, flags=re.S)
        p.write_text(text)
        return 0
    print(bodies["fmi2"] + "\n\n" + bodies["fmi3"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
