"""CoppeliaSim object paths (``sim.getObject``) resolved over a scene's object tree.

A pure function of the tree: entries carry ``handle``, ``name`` (old-style name, may end in
``#n``), ``alias`` (4.x alias; empty in V-REP-era scenes, then the name without its ``#`` suffix
stands in) and ``parent`` (None or -1 at the scene root). The rules are those the CoppeliaSim
manual gives (``accessingSceneObjects``) for unassociated code such as a remote API client:

- ``/A/B/C``: each element is searched among the *descendants* (at any depth) of the previous
  match, so ``/robot/joint`` finds ``/robot/body/joint`` when the alias is unique there. The first
  element is searched in the whole scene.
- ``*`` and ``?`` in an element are wildcards.
- ``A[n]``: only the n-th object (from 0) with that alias among its siblings.
- ``A{n}`` (or the ``index`` option): the n-th match overall instead of the first.
- ``./A`` and ``:/A`` mean ``/A``: a remote client has no script object to be relative to.
  ``.``, ``..``, ``:`` and ``::`` name nothing for it.
- A string without a leading ``/``, ``.`` or ``:`` is an old-style object name (``leftMotor#0``),
  as ``sim.getObjectHandle`` took before 4.3.

When several objects match, they come in the order of the scene hierarchy as CoppeliaSim's
hierarchy view lists it (depth first, siblings in scene order), so ``{n}`` counts objects the way
a user counts them on screen. Why a pure function: it is tested on hand-made trees and serves any
World that can list its tree.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from fnmatch import fnmatchcase
from typing import Any, Protocol


class Node(Protocol):
    handle: int
    name: str
    alias: str
    parent: int | None


@dataclass(frozen=True)
class Entry:
    """One object of the tree (the shape ``World.tree()`` returns)."""

    handle: int
    name: str
    alias: str
    parent: int | None
    kind: str = "shape"


class PathError(ValueError):
    """The path is not well formed (a CoppeliaSim error too: 'invalid object path')."""


_ELEMENT = re.compile(r"^(?P<alias>[^\[\]{}]*)(?:\[(?P<sib>\d+)\])?(?:\{(?P<nth>\d+)\})?$")


@dataclass(frozen=True)
class Element:
    alias: str
    sibling: int | None = None
    nth: int | None = None


def alias_of(entry: Node) -> str:
    """The alias, or for scenes saved before aliases existed the name without ``#n``."""
    alias = getattr(entry, "alias", "") or ""
    if alias:
        return alias
    name = str(getattr(entry, "name", ""))
    return name.rpartition("#")[0] if "#" in name else name


def is_path(text: str) -> bool:
    return text.startswith(("/", ".", ":"))


def parse(path: str) -> list[Element]:
    """The elements of an absolute (or ``./``, ``:/``) path; PathError when malformed."""
    for prefix in ("./", ":/", "/"):
        if path.startswith(prefix):
            body = path[len(prefix) :]
            break
    else:
        raise PathError(f"{path!r} names no object for a remote API client (no script object)")
    parts = body.split("/")
    if not body or any(p == "" for p in parts):
        raise PathError(f"invalid object path {path!r}")
    out = []
    for part in parts:
        m = _ELEMENT.match(part)
        if m is None or not m.group("alias"):
            raise PathError(f"invalid object path {path!r} (element {part!r})")
        sib, nth = m.group("sib"), m.group("nth")
        out.append(Element(m.group("alias"), int(sib) if sib else None, int(nth) if nth else None))
    return out


class Tree:
    """Children lists and depths of a tree of entries, in the entries' order."""

    def __init__(self, entries: Iterable[Node]):
        self.entries = list(entries)
        self.by_handle = {e.handle: e for e in self.entries}
        self.children: dict[int | None, list[Node]] = {}
        for e in self.entries:
            parent = e.parent if e.parent in self.by_handle else None
            self.children.setdefault(parent, []).append(e)

    def descendants(self, root: int | None) -> list[Node]:
        """Below ``root`` (None: the whole scene), in hierarchy order (depth first)."""
        out: list[Node] = []
        stack = list(reversed(self.children.get(root, [])))
        while stack:
            e = stack.pop()
            out.append(e)
            stack.extend(reversed(self.children.get(e.handle, [])))
        return out

    def sibling_index(self, entry: Node) -> int:
        """Position of ``entry`` among its siblings that share its alias."""
        parent = entry.parent if entry.parent in self.by_handle else None
        same = [e for e in self.children.get(parent, []) if alias_of(e) == alias_of(entry)]
        return next(i for i, e in enumerate(same) if e.handle == entry.handle)


def _matches(tree: Tree, root: int | None, element: Element) -> list[Node]:
    found = [e for e in tree.descendants(root) if fnmatchcase(alias_of(e), element.alias)]
    if element.sibling is not None:
        found = [e for e in found if tree.sibling_index(e) == element.sibling]
    if element.nth is not None:
        found = found[element.nth : element.nth + 1]
    return found


def resolve(entries: Iterable[Node] | Tree, path: str, index: int = 0) -> int | None:
    """Handle of the object ``path`` names (the ``index``-th match), or None when none does."""
    tree = entries if isinstance(entries, Tree) else Tree(entries)
    if not is_path(path):
        return resolve_name(tree.entries, path)
    elements = parse(path)
    roots: list[int | None] = [None]
    for depth, element in enumerate(elements):
        last = depth == len(elements) - 1
        found: list[Node] = []
        seen: set[int] = set()
        for root in roots:
            for e in _matches(tree, root, element):
                if e.handle not in seen:
                    seen.add(e.handle)
                    found.append(e)
        if not found:
            return None
        if last:
            return found[index].handle if 0 <= index < len(found) else None
        roots = [e.handle for e in found]
    return None  # pragma: no cover - elements is never empty


def resolve_name(entries: Sequence[Node], name: str) -> int | None:
    """Old-style name lookup: exact name, then ``name#``/``name#0`` as ``name``, then alias."""
    for e in entries:
        if e.name == name:
            return e.handle
    if "#" in name:
        base, _, suffix = name.rpartition("#")
        if suffix in ("", "0"):
            return resolve_name(entries, base)
        return None
    for e in entries:
        if alias_of(e) == name:
            return e.handle
    return None


def full_path(entries: Iterable[Node] | Tree, handle: int) -> str:
    """``/a/b/c``: the aliases from the root down to ``handle`` (CoppeliaSim's full alias path)."""
    tree = entries if isinstance(entries, Tree) else Tree(entries)
    parts = []
    entry: Any = tree.by_handle.get(handle)
    while entry is not None:
        parts.append(alias_of(entry))
        entry = tree.by_handle.get(entry.parent) if entry.parent is not None else None
    return "/" + "/".join(reversed(parts))


def nearest(entries: Iterable[Node] | Tree, path: str, count: int = 3) -> tuple[str, ...]:
    """The scene's full paths (or names, for an old-style name) closest to ``path``."""
    import difflib

    tree = entries if isinstance(entries, Tree) else Tree(entries)
    if is_path(path):
        pool = sorted({full_path(tree, e.handle) for e in tree.entries})
        query = "/" + path.lstrip("./:")
    else:
        pool = sorted({e.name for e in tree.entries} | {alias_of(e) for e in tree.entries})
        query = path
    return tuple(difflib.get_close_matches(query, pool, n=count, cutoff=0.5))
