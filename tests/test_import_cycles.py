"""The packages' modules import each other in one direction: no import circles.

A circle (``a`` imports ``b`` imports ``a``) works only while someone keeps the imports inside
functions or in the right order; it makes a module impossible to read or test on its own. This
walks every module's imports with ``ast`` -- top-level, inside functions, under
``TYPE_CHECKING``, and ``importlib.import_module("x.y")`` with a literal name, so a plugin
table of strings does not hide a dependency -- and fails on every strongly connected
component of more than one module, printing the edges that close it.

What counts as an edge from module ``m``:
- ``import a.b.c`` and ``from a.b.c import x``: ``a.b.c``, and ``a.b.c.x`` when that is a
  module (``from pkg import sub``), else ``a.b.c`` only;
- the packages above the target (``a``, ``a.b``: Python runs their ``__init__`` first),
  except ``m``'s own packages, which are already being imported when ``m`` runs;
- a package's ``__init__`` importing its submodules (re-exports) counts like any module.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("located", "roster", "sims", "sitegen")


def project_modules() -> dict[str, Path]:
    """Dotted module name -> file, for every ``.py`` file under the packages."""
    mods: dict[str, Path] = {}
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg).rglob("*.py")):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            mods[".".join(parts)] = path
    return mods


def _ancestors(name: str) -> list[str]:
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(1, len(parts))]


def _imported_names(tree: ast.AST, module: str, is_package: bool) -> list[tuple[str, int]]:
    """(dotted name, line) for every import in the tree, relative imports resolved."""
    package = module.split(".") if is_package else module.split(".")[:-1]
    found: list[tuple[str, int]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(alias.name, node.lineno) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package[: len(package) - (node.level - 1)]
                base = ".".join(up + ([base] if base else []))
            found.append((base, node.lineno))
            found += [(f"{base}.{alias.name}", node.lineno) for alias in node.names]
        elif (
            isinstance(node, ast.Call)
            and _call_name(node.func) in ("importlib.import_module", "import_module", "__import__")
            and node.args
            and isinstance(node.args[0], ast.Constant)
            and isinstance(node.args[0].value, str)
        ):
            found.append((node.args[0].value, node.lineno))
    return found


def _call_name(func: ast.expr) -> str:
    if isinstance(func, ast.Name):
        return func.id
    if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name):
        return f"{func.value.id}.{func.attr}"
    return ""


def import_graph(mods: dict[str, Path]) -> dict[str, dict[str, int]]:
    """module -> {imported project module: first line importing it}."""
    graph: dict[str, dict[str, int]] = {m: {} for m in mods}
    for module, path in mods.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        own = set(_ancestors(module))
        for name, line in _imported_names(tree, module, path.name == "__init__.py"):
            target = name
            while target and target not in mods:  # `from pkg import name`: name is no module
                target = target.rpartition(".")[0]
            if not target:
                continue
            for dep in [*_ancestors(target), target]:
                if dep != module and dep not in own and dep in mods:
                    graph[module].setdefault(dep, line)
    return graph


def cycles(graph: dict[str, dict[str, int]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, edges = work[-1]
            for nxt in edges:
                if nxt not in index:
                    index[nxt] = low[nxt] = len(index)
                    stack.append(nxt)
                    on_stack.add(nxt)
                    work.append((nxt, iter(sorted(graph[nxt]))))
                    break
                if nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
            else:
                work.pop()
                if work:
                    parent = work[-1][0]
                    low[parent] = min(low[parent], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
    return sorted(found)


def describe(component: list[str], graph: dict[str, dict[str, int]], mods) -> str:
    inside = set(component)
    edges = [
        f"    {m} -> {dep}  ({mods[m].relative_to(ROOT)}:{line})"
        for m in component
        for dep, line in sorted(graph[m].items())
        if dep in inside
    ]
    return f"  {len(component)} modules: {', '.join(component)}\n" + "\n".join(edges)


def test_the_walker_sees_each_kind_of_import(tmp_path):
    """The checker itself: a circle closed by each kind of import is found."""
    kinds = {
        "function-level": "def f():\n    from pkg import a\n",
        "from-package-import-module": "from pkg import a\n",
        "relative": "from . import a\n",
        "type-checking": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import pkg.a\n",
        "import_module": "import importlib\nimportlib.import_module('pkg.a')\n",
        "parent package": "import pkg.sub.c\n",
    }
    for kind, source in kinds.items():
        mods = {"pkg": tmp_path / "pkg" / "__init__.py", "pkg.a": tmp_path / "a.py"}
        mods["pkg.sub"] = tmp_path / "pkg" / "sub" / "__init__.py"
        mods["pkg.sub.c"] = tmp_path / "c.py"
        mods["pkg.b"] = tmp_path / "b.py"
        for path in mods.values():
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text("")
        mods["pkg.a"].write_text("from pkg.b import x\n")
        if kind == "parent package":
            mods["pkg.sub"].write_text("from pkg import a\n")
        mods["pkg.b"].write_text(source)
        assert cycles(import_graph(mods)), kind
    # and a package re-exporting its own submodules is not a circle
    mods["pkg"].write_text("from .a import x\nfrom . import b\n")
    mods["pkg.a"].write_text("from pkg.b import y\n")
    mods["pkg.b"].write_text("import os\n")
    mods["pkg.sub"].write_text("")
    assert cycles(import_graph(mods)) == []


def test_no_import_cycles():
    mods = project_modules()
    graph = import_graph(mods)
    found = cycles(graph)
    report = "\n".join(describe(c, graph, mods) for c in found)
    assert not found, f"{len(found)} import circle(s):\n{report}"
