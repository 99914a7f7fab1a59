"""No module outside the World's own files reaches a private attribute of a World (issue 34):
other packages go through World's public accessors (``world.joint(h)``, ``motor_command``,
``proximity_sensor``, ``object_ref``...), so the World can change how it keeps its state.

Read with ``ast``: an attribute ``_x`` that World (or one of its mixins) defines, reached on an
expression that names a world (``world``, ``w``, ``....world``)."""

from __future__ import annotations

import ast
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
#: the World and its mixins: their own files may use their private state
OWN = {
    "sims/world.py",
    "sims/world_drawing.py",
    "sims/world_holds.py",
    "sims/world_mech.py",
    "sims/world_objects.py",
    "sims/world_tree.py",
    "sims/joint_motors.py",
}
WORLD_NAMES = {"world", "w", "_world"}


def _private_names() -> set[str]:
    """Private attributes World's files define: methods and ``self._x = ...`` fields."""
    names: set[str] = set()
    for rel in OWN:
        tree = ast.parse((REPO / rel).read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                names.add(node.name)
            elif isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
                if node.value.id == "self" and isinstance(node.ctx, ast.Store):
                    names.add(node.attr)
            elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                names.add(node.target.id)
    return {n for n in names if n.startswith("_") and not n.startswith("__")}


def _names_a_world(node: ast.expr) -> bool:
    if isinstance(node, ast.Name):
        return node.id in WORLD_NAMES
    if isinstance(node, ast.Attribute):
        return node.attr in WORLD_NAMES
    return False


def _reaches(source: str, private: set[str]) -> list[tuple[int, str]]:
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Attribute) and node.attr in private:
            if _names_a_world(node.value):
                found.append((node.lineno, node.attr))
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            # getattr(world, "_x") / hasattr(world, "_x") / setattr(world, "_x", v)
            if node.func.id in ("getattr", "hasattr", "setattr") and len(node.args) >= 2:
                what, name = node.args[0], node.args[1]
                if (
                    _names_a_world(what)
                    and isinstance(name, ast.Constant)
                    and isinstance(name.value, str)
                    and name.value.startswith("_")
                    and not name.value.startswith("__")
                ):
                    found.append((node.lineno, name.value))
    return sorted(found)


def test_the_check_sees_private_access():
    private = {"_joints", "_renderer"}
    code = "def f(world, c):\n    world._joints\n    c.world._renderer.x()\n    getattr(w, '_a')\n"
    assert _reaches(code, private) == [(2, "_joints"), (3, "_renderer"), (4, "_a")]
    assert _reaches("def f(world):\n    world.joint(1)\n    self._joints\n", private) == []


def test_no_module_outside_the_world_reaches_its_private_state():
    private = _private_names()
    assert {"_joints", "_objects", "_commands", "_sensors", "_renderer"} <= private
    offenders = []
    for path in sorted((REPO / "sims").rglob("*.py")) + sorted((REPO / "sitegen").rglob("*.py")):
        rel = path.relative_to(REPO).as_posix()
        if rel in OWN:
            continue
        for line, name in _reaches(path.read_text(encoding="utf-8"), private):
            offenders.append(f"{rel}:{line}: {name}")
    assert offenders == []
