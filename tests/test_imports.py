"""The package's imports point one way: no cycle, no function-local import of the package
(except in ``cli``, which imports each command's stages when the command runs, so that
``--help`` answers at once), no module imports a stage later in the workflow than its own
(function-local imports included), and no stage imports a peer stage (another subpackage of
its rank).

Layers (lower may be imported by higher, never the reverse; peers on one line do not import
each other)::

    effects (the effect registry)
    <- paper, data, data_csv, signals, model_description, inputs, outputs  <- physics, plausibility
    <- model_file, fits (fits identification and diagnosis share)
    <- fmu (fmu2, fmu3: its FMI 2.0 and 3.0 adapters; fmu_extraction), export_fmu <- control
    <- harness (closed loop, sidecar, checked runs) <- experiments (the campaign, Secs. 3 and 4)
    <- residual (the force residual), systems (SSP, OSP, container)
    <- identify, validation, diagnose, realdata, xy (the X-Y table and its circular test)
    <- study <- report <- commands, bench_agreement, bench_c, bench_campaign, bench_engines,
       bench_study
    <- cli (the parser), bench_cli (times it), bench (the `make bench` table)
"""

from __future__ import annotations

import ast
from pathlib import Path

import feeddrive

PKG = Path(feeddrive.__file__).resolve().parent

#: rank of each top-level module or subpackage of feeddrive (imports only to rank <= own)
LAYERS: dict[str, int] = {
    "effects": -1,
    "paper": 0,
    "data": 0,
    "data_csv": 0,
    "signals": 0,
    "model_description": 0,
    "outputs": 0,
    "inputs": 0,
    "physics": 1,
    "plausibility": 1,
    "model_file": 2,
    "fits": 2,
    "fmu": 3,
    "fmu2": 3,
    "fmu3": 3,
    "fmu_extraction": 3,
    "export_fmu": 3,
    "control": 4,
    "harness": 5,
    "experiments": 6,
    "residual": 7,
    "systems": 7,
    "identify": 8,
    "validation": 8,
    "diagnose": 8,
    "realdata": 8,
    "xy": 8,
    "study": 9,
    "report": 10,
    "cli": 12,
    "commands": 11,
    "bench": 12,
    "bench_agreement": 11,
    "bench_c": 11,
    "bench_campaign": 11,
    "bench_engines": 11,
    "bench_cli": 12,
    "bench_study": 11,
    "__main__": 12,
}


def _module_name(path: Path) -> str:
    rel = path.relative_to(PKG.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _resolve(mod: str, is_pkg: bool, node: ast.ImportFrom) -> str:
    if node.level == 0:
        return node.module or ""
    base = mod.split(".") if is_pkg else mod.split(".")[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(path: Path) -> list[tuple[str, int, bool]]:
    """(imported feeddrive module, line, inside a function) for every import in ``path``."""
    mod = _module_name(path)
    is_pkg = path.name == "__init__.py"
    tree = ast.parse(path.read_text(), str(path))
    out: list[tuple[str, int, bool]] = []

    def visit(node: ast.AST, in_func: bool) -> None:
        for child in ast.iter_child_nodes(node):
            f = in_func or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef))
            if isinstance(child, ast.Import):
                out.extend(
                    (a.name, child.lineno, in_func)
                    for a in child.names
                    if a.name.split(".")[0] == "feeddrive"
                )
            elif isinstance(child, ast.ImportFrom):
                target = _resolve(mod, is_pkg, child)
                if target.split(".")[0] == "feeddrive":
                    if child.module is None or target == "feeddrive":
                        # from . import x / from .. import x: x may be a module
                        for a in child.names:
                            out.append((f"{target}.{a.name}", child.lineno, in_func))
                    else:
                        out.append((target, child.lineno, in_func))
            visit(child, f)

    visit(tree, False)
    return out


def _graph() -> dict[str, set[str]]:
    mods = {_module_name(p): p for p in PKG.rglob("*.py")}
    g: dict[str, set[str]] = {m: set() for m in mods}
    for m, p in mods.items():
        for target, _, _ in _imports(p):
            while target not in mods and "." in target:  # an attribute, not a module
                target = target.rsplit(".", 1)[0]
            if target in mods and target != m:
                g[m].add(target)
    return g


def _layer(mod: str) -> int | None:
    parts = mod.split(".")
    return LAYERS.get(parts[1]) if len(parts) > 1 else None


def test_no_import_cycle() -> None:
    g = _graph()
    # Tarjan's strongly connected components
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    cycles: list[list[str]] = []
    counter = [0]

    def strong(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in g[v]:
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in sorted(g):
        if v not in index:
            strong(v)
    # a package __init__ re-exporting its own modules is not a cycle of the flow
    real = [
        c
        for c in cycles
        if not all(x.startswith(min(c, key=len) + ".") or x == min(c, key=len) for x in c)
    ]
    assert not real, f"import cycles: {real}"


#: the modules (and their submodules) that may import the package inside functions (lazy
#: loading of the commands)
LAZY = {"feeddrive.cli"}


def test_no_function_local_package_import() -> None:
    bad = [
        f"{p.relative_to(PKG.parent)}:{line} imports {t}"
        for p in sorted(PKG.rglob("*.py"))
        if not any(_module_name(p) == m or _module_name(p).startswith(m + ".") for m in LAZY)
        for t, line, in_func in _imports(p)
        if in_func
    ]
    assert not bad, "function-local imports of the package:\n" + "\n".join(bad)


def _package_imports() -> list[tuple[str, str, str]]:
    """(file:line, importing module, imported module) for every import of the package."""
    return [
        (f"{p.relative_to(PKG.parent)}:{line}", _module_name(p), t)
        for p in sorted(PKG.rglob("*.py"))
        for t, line, _ in _imports(p)
    ]


def test_imports_point_down_the_flow() -> None:
    bad = []
    for where, mod, t in _package_imports():
        own, other = _layer(mod), _layer(t)
        if own is not None and other is not None and other > own:
            bad.append(f"{where} ({mod.split('.')[1]}, layer {own}) imports {t} (layer {other})")
    assert not bad, "imports against the flow:\n" + "\n".join(bad)


def test_every_module_has_a_layer() -> None:
    missing = sorted({m.split(".")[1] for m in _graph() if m.count(".") >= 1 and _layer(m) is None})
    assert not missing, f"modules with no layer in LAYERS: {missing}"


def _stage(mod: str) -> str | None:
    """The top-level subpackage (a folder, not a module) ``mod`` belongs to, if any."""
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 and (PKG / parts[1]).is_dir() else None


def test_peer_stages_do_not_import_each_other() -> None:
    bad = []
    for where, mod, t in _package_imports():
        own, other = _stage(mod), _stage(t)
        if own is None or other is None or other == own or _layer(t) != _layer(mod):
            continue
        bad.append(f"{where} ({own}) imports {t} (its peer {other}, layer {_layer(mod)})")
    assert not bad, "imports between peer stages:\n" + "\n".join(bad)
