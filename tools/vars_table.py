#!/usr/bin/env python3
"""Print the Markdown tables of the FMU's variables, generated from modelDescription.xml: the FMI 2.0
variables and the FMI 3.0 variables that differ from them (arrays of dimension friction.N, the
structural parameter, time, eventIndicators; from the FMI 3.0 description fmu_src/generators/gen_fmi3.py
derives from the same file) for docs/variables.md, and every parameter with its unit, default
and allowed range for docs/parameters.md.

Usage: vars_table.py                   print the tables
       vars_table.py --check FILE...   verify that every table block in each FILE is current
       vars_table.py --update FILE...  rewrite the table blocks of each FILE

A block is the text between its markers, e.g. <!-- parameters:begin --> and
<!-- parameters:end -->; a FILE must hold at least one.
"""

from __future__ import annotations

import importlib.util
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BLOCKS = {
    "fmi2": ("<!-- variables:begin -->", "<!-- variables:end -->"),
    "fmi3": ("<!-- variables3:begin -->", "<!-- variables3:end -->"),
    "params": ("<!-- parameters:begin -->", "<!-- parameters:end -->"),
}


def table(xml_path: Path) -> str:
    root = ET.parse(xml_path).getroot()
    rows = [
        "| name | causality | variability | type | unit | default | description |",
        "|---|---|---|---|---|---|---|",
    ]
    for sv in root.find("ModelVariables").findall("ScalarVariable"):
        t = sv[0]
        desc = sv.get("description", "").replace("|", "/")
        rows.append(
            f"| `{sv.get('name')}` | {sv.get('causality', 'local')} | {sv.get('variability', 'continuous')} "
            f"| {t.tag} | {t.get('unit', '')} | {t.get('start', '')} | {desc} |"
        )
    return "\n".join(rows)


def _num(text: str | None) -> str:
    """A number of the XML as the table shows it ('' when absent)."""
    if text is None:
        return ""
    v = float(text)
    return f"{v:.12g}" if v == v and abs(v) < 1e16 else text


def params_table(xml_path: Path) -> str:
    """Every parameter (causality parameter or structuralParameter): unit, default, range, effect."""
    root = ET.parse(xml_path).getroot()
    rows = [
        "| name | unit | default | min | max | tunable | description |",
        "|---|---|---|---|---|---|---|",
    ]
    for sv in root.find("ModelVariables").findall("ScalarVariable"):
        if sv.get("causality") != "parameter":
            continue
        t = sv[0]
        desc = sv.get("description", "").replace("|", "/")
        if t.tag == "Boolean":
            lo = hi = ""
            default = t.get("start", "")
        else:
            lo, hi, default = _num(t.get("min")), _num(t.get("max")), _num(t.get("start"))
        rows.append(
            f"| `{sv.get('name')}` | {t.get('unit', '')} | {default} | {lo} | {hi} "
            f"| {'yes' if sv.get('variability') == 'tunable' else 'no'} | {desc} |"
        )
    return "\n".join(rows)


def _gen_fmi3():
    spec = importlib.util.spec_from_file_location(
        "gen_fmi3", ROOT / "fmu_src" / "generators" / "gen_fmi3.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def table3(xml_path: Path) -> str:
    """The FMI 3.0 variables that are not an FMI 2.0 scalar of the same name."""
    gen = _gen_fmi3()
    rows = [
        "| name | value reference | causality | type | dimension | unit | default | FMI 2.0 |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for v in gen.fmi3_variables(ET.parse(xml_path).getroot()):
        changed = (
            v["name"] in ("time", "eventIndicators")
            or v["dim"]
            or v["attrs"]["causality"] == "structuralParameter"
        )
        if not changed:
            continue
        dim = "friction.N" if v["dim"] else (str(v["nz"]) if "nz" in v else "")
        e = v["elems"]
        if v["dim"]:
            elem = "der(friction.F[k])" if v["name"].startswith("der(") else f"{v['name']}[k]"
            step = ", ..., " if e[1] - e[0] > 1 else ".."
            second = f", {e[1]}" if step != ".." else ""
            was = f"`{elem}`, k = 1..10 (value references {e[0]}{second}{step}{e[-1]})"
        else:
            was = {
                "time": "— (independent variable)",
                "eventIndicators": "`numberOfEventIndicators`",
            }.get(v["name"], f"`{v['name']}` (parameter)")
        rows.append(
            f"| `{v['name']}` | {v['vr']} | {v['attrs']['causality']} | {v['type']} | {dim} "
            f"| {v['typed'].get('unit', '')} | {v['typed'].get('start', '')} | {was} |"
        )
    return "\n".join(rows)


def _current(text: str, key: str, body: str) -> bool:
    begin, end = BLOCKS[key]
    m = re.search(re.escape(begin) + r"(.*?)" + re.escape(end), text, re.S)
    return bool(m) and m.group(1).strip() == body.strip()


def _blocks_in(text: str) -> list[str]:
    return [k for k, (begin, _) in BLOCKS.items() if begin in text]


def main() -> int:
    xml = ROOT / "modelDescription.xml"
    makers = {"fmi2": table, "fmi3": table3, "params": params_table}
    if len(sys.argv) >= 3 and sys.argv[1] in ("--check", "--update"):
        status = 0
        for name in sys.argv[2:]:
            p = Path(name)
            text = p.read_text()
            keys = _blocks_in(text)
            if not keys:
                print(f"{p}: no table block (markers such as {BLOCKS['params'][0]})")
                return 2
            bodies = {k: makers[k](xml) for k in keys}
            if sys.argv[1] == "--check":
                if not all(_current(text, k, b) for k, b in bodies.items()):
                    print(
                        f"{p}: the variables table is not current; run tools/vars_table.py --update {p}"
                    )
                    status = 1
                continue
            for key, body in bodies.items():
                begin, end = BLOCKS[key]
                text = re.sub(
                    re.escape(begin) + r".*?" + re.escape(end),
                    lambda _, begin=begin, body=body, end=end: begin + "\n" + body + "\n" + end,
                    text,
                    flags=re.S,
                )
            p.write_text(text)
        return status
    print(table(xml) + "\n\n" + table3(xml) + "\n\n" + params_table(xml))
    return 0


if __name__ == "__main__":
    sys.exit(main())
