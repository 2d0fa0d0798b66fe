"""Which product files name each effect of the catalogue (docs/adding-an-effect.md).

A file names effect ``<id>`` when it holds its switch ``effects.<id>``, the id as a string
literal (a Python string constant equal to the id; ``"<id>"`` or ``'<id>'`` in C and XML),
a registry symbol ``effect_<id>`` / ``EFFECT_<ID>``, or (Python) imports the effect's module
``feeddrive.effects.<id>``.  The product files are ``python/feeddrive/**/*.py``,
``fmu_src/**`` (``.c``, ``.h``, ``.py``, ``.xml``) and ``modelDescription.xml``.

Usage: ``python tools/effect_names.py [ROOT]`` prints the count and the files per effect.
"""

from __future__ import annotations

import argparse
import ast
import re
import sys
from collections.abc import Iterable
from pathlib import Path

#: The product folders and files searched, relative to the repository root, with the suffixes.
SOURCES: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("python/feeddrive", (".py",)),
    ("fmu_src", (".c", ".h", ".py", ".xml")),
    ("modelDescription.xml", (".xml",)),
)


def product_files(root: Path) -> list[Path]:
    """Every product file under ``root`` (:data:`SOURCES`), sorted."""
    out: list[Path] = []
    for rel, suffixes in SOURCES:
        p = root / rel
        if p.is_file():
            out.append(p)
        elif p.is_dir():
            out += [
                f
                for f in p.rglob("*")
                if f.is_file() and f.suffix in suffixes and "__pycache__" not in f.parts
            ]
    return sorted(out)


def _text_patterns(effect_id: str, literal: bool) -> re.Pattern[str]:
    parts = [
        rf"\beffects\.{effect_id}\b",
        rf"\beffect_{effect_id}\b",
        rf"\bEFFECT_{effect_id.upper()}\b",
    ]
    if literal:
        parts.append(rf"([\"']){effect_id}\1")
    return re.compile("|".join(parts))


def _module_name(path: Path, root: Path) -> tuple[str, bool]:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[0] == "python":
        parts = parts[1:]
    is_pkg = parts[-1] == "__init__"
    return ".".join(parts[:-1] if is_pkg else parts), is_pkg


def _python_names(tree: ast.AST, module: str, is_pkg: bool) -> set[str]:
    """The string constants of ``tree`` and the ids of the effect modules it imports."""
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            out.add(node.value)
        elif isinstance(node, ast.Import):
            out.update(
                a.name.removeprefix("feeddrive.effects.")
                for a in node.names
                if a.name.startswith("feeddrive.effects.")
            )
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = module.split(".") if is_pkg else module.split(".")[:-1]
                base = base[: len(base) - (node.level - 1)]
                src = ".".join(base + ([node.module] if node.module else []))
            else:
                src = node.module or ""
            if src == "feeddrive.effects":
                out.update(a.name for a in node.names)
            elif src.startswith("feeddrive.effects."):
                out.add(src.removeprefix("feeddrive.effects."))
    return out


def named_effects(path: Path, root: Path, effect_ids: Iterable[str]) -> set[str]:
    """The ids of ``effect_ids`` the product file ``path`` names (module docstring)."""
    text = path.read_text(encoding="utf-8", errors="replace")
    python = path.suffix == ".py"
    found = {e for e in effect_ids if _text_patterns(e, literal=not python).search(text)}
    if python:
        module, is_pkg = _module_name(path, root)
        found |= set(effect_ids) & _python_names(ast.parse(text, str(path)), module, is_pkg)
    return found


def naming_files(root: Path, effect_ids: Iterable[str]) -> dict[str, list[str]]:
    """For each effect id, the product files (paths relative to ``root``) that name it."""
    ids = list(effect_ids)
    out: dict[str, list[str]] = {e: [] for e in ids}
    for f in product_files(root):
        for e in named_effects(f, root, ids):
            out[e].append(str(f.relative_to(root)))
    return {e: sorted(files) for e, files in out.items()}


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(
        description="Print, for each effect of the catalogue, how many product files name it "
        "and which (the rule: this module's docstring, docs/adding-an-effect.md)."
    )
    ap.add_argument(
        "root",
        nargs="?",
        type=Path,
        default=Path(__file__).resolve().parents[1],
        help="the repository's root (default: the one this tool is in)",
    )
    a = ap.parse_args(argv)
    root: Path = a.root
    if not (root / "python" / "feeddrive" / "effects").is_dir():
        print(f"{root}: not a feeddrive checkout (no python/feeddrive/effects/)", file=sys.stderr)
        return 2
    sys.path.insert(0, str(root / "python"))
    from feeddrive.effects import effect_ids

    for e, files in naming_files(root, effect_ids()).items():
        print(f"{e:20s} {len(files):2d}  " + " ".join(files))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
