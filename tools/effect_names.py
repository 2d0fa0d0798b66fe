"""Which product files name each effect of the catalogue (docs/adding-an-effect.md).

A file names effect ``<id>`` when it holds its switch ``effects.<id>``, the id as a string
literal (a Python string constant equal to the id; ``"<id>"`` or ``'<id>'`` in C and XML),
a registry symbol ``effect_<id>`` / ``EFFECT_<ID>``, or (Python) imports the effect's module
``feeddrive.effects.<id>``.  The product files are ``python/feeddrive/**/*.py``,
``fmu_src/**`` (``.c``, ``.h``, ``.py``, ``.xml``) and ``modelDescription.xml``.

Usage: ``python tools/effect_names.py [ROOT]`` prints the count and the files per effect.
"""
from __future__ import annotations

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
            out += [f for f in p.rglob("*") if f.is_file() and f.suffix in suffixes
                    and "__pycache__" not in f.parts]
    return sorted(out)


def _text_patterns(effect_id: str, literal: bool) -> re.Pattern[str]:
    parts = [rf"\beffects\.{effect_id}\b", rf"\beffect_{effect_id}\b",
             rf"\bEFFECT_{effect_id.upper()}\b"]
    if literal:
        parts.append(rf"([\"']){effect_id}\1")
    return re.compile("|".join(parts))


def _python_names(tree: ast.AST, module: str, is_pkg: bool, effect_id: str) -> bool:
    """A string constant equal to the id, or an import of ``feeddrive.effects.<id>``."""
    target_mod = f"feeddrive.effects.{effect_id}"
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and node.value == effect_id:
            return True
        if isinstance(node, ast.Import) and any(a.name == target_mod for a in node.names):
            return True
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = module.split(".") if is_pkg else module.split(".")[:-1]
                base = base[: len(base) - (node.level - 1)]
                src = ".".join(base + ([node.module] if node.module else []))
            else:
                src = node.module or ""
            if src == target_mod or (src == "feeddrive.effects"
                                     and any(a.name == effect_id for a in node.names)):
                return True
    return False


def names_effect(path: Path, root: Path, effect_id: str) -> bool:
    """Whether the product file ``path`` names ``effect_id`` (module docstring)."""
    text = path.read_text(encoding="utf-8", errors="replace")
    if path.suffix == ".py":
        if _text_patterns(effect_id, literal=False).search(text):
            return True
        rel = path.relative_to(root)
        parts = list(rel.with_suffix("").parts)
        if parts[0] == "python":
            parts = parts[1:]
        is_pkg = parts[-1] == "__init__"
        module = ".".join(parts[:-1] if is_pkg else parts)
        return _python_names(ast.parse(text, str(path)), module, is_pkg, effect_id)
    return _text_patterns(effect_id, literal=True).search(text) is not None


def naming_files(root: Path, effect_ids: Iterable[str]) -> dict[str, list[str]]:
    """For each effect id, the product files (paths relative to ``root``) that name it."""
    files = product_files(root)
    return {e: [str(f.relative_to(root)) for f in files if names_effect(f, root, e)]
            for e in effect_ids}


def main(argv: list[str]) -> int:
    root = Path(argv[0]) if argv else Path(__file__).resolve().parents[1]
    sys.path.insert(0, str(root / "python"))
    from feeddrive.effects import effect_ids
    for e, files in naming_files(root, effect_ids()).items():
        print(f"{e:20s} {len(files):2d}  " + " ".join(files))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
