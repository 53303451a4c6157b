"""The layering contract, enforced: data flows one way through the packages.

    cli
    batch
    viz
    control                               (controllers over dynamics)
    robots
    particles | dynamics | symbolic      (siblings: no imports between them; massprops and _core only)
    massprops
    geometry
    _core                                 (numpy, scipy and the standard library only)

A package may import the packages listed for it in ``ALLOWED`` and itself (the import table of
the target layout: a row imports the rows below it, with the exceptions listed there; the
compiled core ``inertia._ext`` only from the layers that own its kernels: geometry, massprops (the
canonical principal frame) and dynamics).  The public
facade (``inertia/__init__.py``, ``inertia/errors.py``) may import anything; nothing inside
imports the facade.  Every import is checked, including those inside functions (lazy
imports are still dependencies).  Also: no private name (``_x``, not a dunder) imported from
another module, and no import cycle between modules.
"""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"
PKG = SRC / "inertia"

ALLOWED = {
    "_core": set(),
    "geometry": {"_core", "_ext"},   # _ext: the compiled core (its geometry families)
    "massprops": {"geometry", "_core", "_ext"},   # _ext: the canonical principal frame
    "particles": {"massprops", "_core"},
    "dynamics": {"massprops", "_core", "_ext"},   # _ext: the compiled core (its dynamics kernels)
    "symbolic": {"massprops", "_core"},
    "robots": {"massprops", "geometry", "_core"},
    "control": {"dynamics", "massprops", "_core"},
    "viz": {"control", "particles", "dynamics", "massprops", "geometry", "_core"},
    "batch": {"robots", "massprops", "geometry", "_core"},
    "cli": {"batch", "viz", "control", "robots", "symbolic", "dynamics", "particles", "massprops", "geometry",
            "_core"},
}
FACADE = {"inertia", "inertia.errors"}


def _module_name(path: Path) -> str:
    parts = path.relative_to(SRC).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in sorted(PKG.rglob("*.py"))}


def _resolve(mod: str, is_pkg: bool, level: int, target: str | None) -> str:
    if level == 0:
        return target or ""
    base = mod.split(".") if is_pkg else mod.split(".")[:-1]
    base = base[: len(base) - (level - 1)]
    return ".".join(base + ([target] if target else []))


def _imports(mod: str, path: Path):
    """Yield ``(line, imported_module, imported_name_or_None)`` for every import in the file."""
    tree = ast.parse(path.read_text(), str(path))
    is_pkg = path.name == "__init__.py"
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield node.lineno, a.name, None
        elif isinstance(node, ast.ImportFrom):
            src = _resolve(mod, is_pkg, node.level, node.module)
            for a in node.names:
                yield node.lineno, src, a.name


def _layer(mod: str) -> str | None:
    parts = mod.split(".")
    if mod in FACADE or len(parts) < 2:
        return None
    return parts[1]


def _internal_edges():
    """``(src_module, dst_module, line, name)`` for imports of inertia modules (name resolved to
    a submodule when it is one)."""
    mods = _modules()
    for mod, path in mods.items():
        for line, target, name in _imports(mod, path):
            if not (target == "inertia" or target.startswith("inertia.")):
                continue
            sub = f"{target}.{name}" if name else None
            dst = sub if sub in mods else target
            yield mod, dst, line, (None if sub in mods else name), path


def test_every_import_follows_the_layers():
    bad = []
    for mod, dst, line, _name, path in _internal_edges():
        src_layer = _layer(mod)
        if src_layer is None:
            continue                         # the facade may import anything
        if dst in FACADE:
            bad.append(f"{path.relative_to(SRC)}:{line}: imports the public facade {dst} (use inertia._core...)")
            continue
        dst_layer = _layer(dst)
        if dst_layer and dst_layer != src_layer and dst_layer not in ALLOWED[src_layer]:
            bad.append(f"{path.relative_to(SRC)}:{line}: {src_layer} may not import {dst_layer} ({dst})")
    assert not bad, "imports against the layers:\n" + "\n".join(bad)


def test_no_private_name_crosses_modules():
    bad = []
    for mod, dst, line, name, path in _internal_edges():
        if name and name.startswith("_") and not name.startswith("__") and dst != mod:
            bad.append(f"{path.relative_to(SRC)}:{line}: imports private name {name} from {dst}")
    assert not bad, "private names imported from another module:\n" + "\n".join(bad)


def test_the_bottom_layer_needs_only_numpy_scipy_and_the_standard_library():
    import sys

    allowed = {"numpy", "scipy", "inertia"} | set(sys.stdlib_module_names)
    bad = []
    for mod, path in _modules().items():
        if _layer(mod) != "_core":
            continue
        for line, target, _ in _imports(mod, path):
            top = target.split(".")[0]
            if top and top not in allowed:
                bad.append(f"{path.relative_to(SRC)}:{line}: imports {target}")
    assert not bad, "\n".join(bad)


def test_no_import_cycles_between_modules():
    graph: dict[str, set[str]] = {}
    for mod, dst, _line, _name, _path in _internal_edges():
        if _layer(mod) is None or dst in FACADE or dst == mod:
            continue
        # a module importing a package's name goes through the package's __init__; skip
        # edges to packages (lazy namespaces) and keep module -> module edges
        graph.setdefault(mod, set()).add(dst)
    mods = _modules()
    pkgs = {m for m, p in mods.items() if p.name == "__init__.py"}
    for k in graph:
        graph[k] -= pkgs
    # Tarjan's strongly connected components
    index, low, stack, on, cycles, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
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

    for v in list(graph):
        if v not in index:
            visit(v)
    assert not cycles, "import cycles: " + "; ".join(" <-> ".join(c) for c in cycles)


def test_the_contract_sees_real_imports():
    # guard against a walker that finds nothing: known edges must be seen
    edges = {(m, d) for m, d, *_ in _internal_edges()}
    assert ("inertia.massprops.mesh", "inertia.geometry.checks") in edges or \
        any(m == "inertia.massprops.mesh" and d.startswith("inertia.geometry.") for m, d in edges)
    assert any(_layer(m) == "cli" for m, _ in edges)
