#!/usr/bin/env python3
"""Print the Markdown table of the FMU's variables from modelDescription.xml (for the README).

Usage: vars_table.py [modelDescription.xml]   — or --check README.md to verify it is current.
"""
from __future__ import annotations

import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BEGIN, END = "<!-- variables:begin -->", "<!-- variables:end -->"


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


def main() -> int:
    xml = ROOT / "modelDescription.xml"
    if len(sys.argv) == 3 and sys.argv[1] == "--check":
        text = Path(sys.argv[2]).read_text()
        m = re.search(re.escape(BEGIN) + r"(.*?)" + re.escape(END), text, re.S)
        if not m or m.group(1).strip() != table(xml).strip():
            print(f"{sys.argv[2]}: the variables table is not current; run tools/vars_table.py --update README.md")
            return 1
        return 0
    if len(sys.argv) == 3 and sys.argv[1] == "--update":
        p = Path(sys.argv[2])
        text = p.read_text()
        new = re.sub(re.escape(BEGIN) + r".*?" + re.escape(END),
                     lambda _: BEGIN + "\n" + table(xml) + "\n" + END, text, flags=re.S)
        p.write_text(new)
        return 0
    print(table(xml))
    return 0


if __name__ == "__main__":
    sys.exit(main())
