"""The one resolver of object names and paths, for the Lua scripts, the legacy API and ZeroMQ.

A pure function of an object tree: entries carry ``handle``, ``name`` (the old-style name, which
may end in ``#n``), ``alias`` (the 4.x alias; empty in V-REP-era scenes, where the name without
its ``#`` suffix stands in, as CoppeliaSim 4.2+ gives such scenes on load) and ``parent``.
Paths follow CoppeliaSim's own search (``CSceneObjectContainer::getObjectFromPath``, read in
coppeliaSimLib), so a script finds what it finds in CoppeliaSim:

- ``/A/B``: ``A`` is searched from the scene root, ``B`` below the match. At each level the
  children are tried in order (a match ends the search), then each child's subtree in turn, so
  ``/robot/joint`` finds a ``joint`` anywhere below ``robot``, the shallowest first.
- ``*`` and ``?`` are wildcards; ``A[n]`` is the n-th ``A`` among siblings; ``A{n}`` (or the
  ``index`` argument) the n-th match of the search.
- Relative to the calling script's object (``base``): ``.`` is that object, ``./A`` searches
  below it, ``:`` is its model (the first model base up from it, itself included), ``:/A``
  below that, ``..`` and ``::`` climb to the parent and to the model above. Unassociated code
  (a remote API client, ``base`` None) has no object: ``./A`` and ``:/A`` search the whole scene
  and ``.``/``:`` name nothing (PathError: there is nothing for them to name).
- Anything else is an old-style name (``sim.getObjectHandle``): the exact name; ``name#`` is
  ``name``; in a script attached to ``robot#1`` a name without ``#`` means ``name#1`` (the
  copied-model rule, ``suffix``); ``name#0`` falls back to ``name`` (the legacy clients' habit);
  then the first object carrying that alias.

Why one module: the Lua layer, the legacy ``simxGetObjectHandle`` and ZeroMQ's
``sim.getObject`` used to resolve with two functions that disagreed.
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
    """One object of a tree (the shape ``World.tree()`` returns)."""

    handle: int
    name: str
    alias: str
    parent: int | None
    kind: str = "shape"
    model: bool = False  # a model base (``:`` stops there)


class PathError(ValueError):
    """The path is not well formed (CoppeliaSim: 'object does not exist, or alias/path is ill
    formatted')."""


_ELEMENT = re.compile(r"^(?P<alias>[^\[\]{}]*)(?:\[(?P<sib>\d+)\])?(?:\{(?P<nth>\d+)\})?$")


def alias_of(entry: Any) -> str:
    """The alias, or for scenes saved before aliases existed the name without ``#n``."""
    alias = getattr(entry, "alias", "") or ""
    if alias:
        return alias
    name = str(getattr(entry, "name", ""))
    return name.rpartition("#")[0] if "#" in name else name


def is_path(text: str) -> bool:
    return text.startswith(("/", ".", ":"))


def parse(path: str) -> list[tuple[str, int | None, int | None]]:
    """Check an absolute path's elements: (alias, sibling index, match index) each; PathError
    when malformed."""
    body = path[1:] if path.startswith("/") else path
    parts = body.split("/")
    if not body or any(p == "" for p in parts):
        raise PathError(f"invalid object path {path!r}")
    out = []
    for part in parts:
        m = _ELEMENT.match(part)
        if m is None or not m.group("alias"):
            raise PathError(f"invalid object path {path!r} (element {part!r})")
        sib, nth = m.group("sib"), m.group("nth")
        out.append((m.group("alias"), int(sib) if sib else None, int(nth) if nth else None))
    return out


class Tree:
    """Children lists of a tree of entries, in the entries' order."""

    def __init__(self, entries: Iterable[Node]):
        self.entries = list(entries)
        self.by_handle = {e.handle: e for e in self.entries}
        self.children: dict[int | None, list[Node]] = {}
        for e in self.entries:
            parent = e.parent if e.parent in self.by_handle else None
            self.children.setdefault(parent, []).append(e)
        self._names: dict[str, int] | None = None

    def name_index(self) -> dict[str, int]:
        if self._names is None:
            self._names = {}
            for e in self.entries:
                self._names.setdefault(e.name, e.handle)
        return self._names

    def parent_of(self, handle: int | None) -> int | None:
        e = self.by_handle.get(handle) if handle is not None else None
        if e is None or e.parent not in self.by_handle:
            return None
        return e.parent

    def model_of(self, handle: int | None, include_self: bool = True) -> int | None:
        h = handle if include_self else self.parent_of(handle)
        while h is not None and not getattr(self.by_handle[h], "model", False):
            h = self.parent_of(h)
        return h

    def descendants(self, root: int | None) -> list[Node]:
        """Below ``root`` (None: the whole scene), depth first (the hierarchy view's order)."""
        out: list[Node] = []
        stack = list(reversed(self.children.get(root, [])))
        while stack:
            e = stack.pop()
            out.append(e)
            stack.extend(reversed(self.children.get(e.handle, [])))
        return out


def _tree(entries: Iterable[Node] | Tree) -> Tree:
    return entries if isinstance(entries, Tree) else Tree(entries)


class _Counter:
    def __init__(self, n: int):
        self.n = n


def _in_tree(tree: Tree, base: int | None, path: str, index: _Counter) -> int | None:
    """CoppeliaSim's ``_getObjectInTree``: the level's children first, then their subtrees."""
    first, sep, rest = path.partition("/")
    name, sibling = first, None
    if "[" in first and first.endswith("]"):
        name, _, num = first[:-1].partition("[")
        sibling = int(num) if num.isdigit() else -1
    deeper: list[Node] = []
    for e in tree.children.get(base, []):
        explore = True
        if fnmatchcase(alias_of(e), name):
            explore = sibling is None
            if not sibling:  # None or 0: this one
                if not sep:
                    if index.n > 0:
                        index.n -= 1
                    else:
                        return e.handle
                else:
                    found = _in_tree(tree, e.handle, rest, index)
                    if found is not None:
                        return found
            if sibling is not None:
                sibling -= 1
        if explore:
            deeper.append(e)
    for e in deeper:
        found = _in_tree(tree, e.handle, path, index)
        if found is not None:
            return found
    return None


def _simple(tree: Tree, base: int | None, path: str, index: _Counter) -> int | None:
    """CoppeliaSim's ``_getObjectFromSimplePath`` (``base``: the calling script's object)."""
    if path.startswith("/"):
        parse(path)
        return _in_tree(tree, None, path[1:], index)
    if path in (".", ":"):
        if base is None:
            raise PathError(f"{path!r} names no object for code without a script object")
        return tree.model_of(base) if path == ":" else base
    at: int | None = base
    if path.startswith("./"):
        path = path[2:]
    elif path.startswith(":/"):
        path = path[2:]
        at = tree.model_of(at) if at is not None else None
    while path.startswith(("::", "..")):
        if at is None:
            if base is None:
                raise PathError(f"{path!r} names no object for code without a script object")
            return None
        model = path.startswith("::")
        path = path[2:]
        if model:
            at = tree.model_of(at)
            if at is None:
                return None
            at = tree.model_of(at, include_self=False)
        else:
            at = tree.parent_of(at)
        if not path:
            return at
        if not path.startswith("/"):
            raise PathError(f"invalid object path (expected '../' or '::/') in {path!r}")
        path = path[1:]
    parse("/" + path)
    return _in_tree(tree, at, path, index)


def _path(tree: Tree, base: int | None, path: str, index: int) -> int | None:
    """CoppeliaSim's ``getObjectFromPath``: ``{n}`` inside a path restarts the search from the
    n-th match, relative to it."""
    while path:
        m = re.search(r"\{(\d+)\}", path)
        if m is not None and (m.end() != len(path) or index < 0):
            head, tail = path[: m.start()], path[m.end() :]
            found = _simple(tree, base, head, _Counter(int(m.group(1))))
            path = "." + tail if tail else ""
        else:
            if m is not None:
                path = path[: m.start()]
                index = int(m.group(1))
            found = _simple(tree, base, path, _Counter(max(index, 0)))
            path = ""
        if found is None:
            return None
        base = found
    return base


def resolve(
    entries: Iterable[Node] | Tree,
    query: str,
    relative_to: int | None = None,
    *,
    index: int = -1,
    base: int | None = None,
    suffix: int | None = None,
) -> int | None:
    """Handle of the object ``query`` names (a path or an old-style name), or None.

    ``index``: the n-th match of a path (-1 or 0: the first); ``base``: the calling script's
    object; ``suffix``: the calling script's object's ``#n`` (the copied-model name rule);
    ``relative_to`` is ``base`` under its older name. PathError for a malformed path."""
    tree = _tree(entries)
    base = base if base is not None else relative_to
    if is_path(query):
        return _path(tree, base, query, index)
    return resolve_name(tree, query, suffix)


def resolve_name(
    entries: Sequence[Node] | Tree, name: str, suffix: int | None = None
) -> int | None:
    """Old-style name lookup: see the module docstring."""
    tree = _tree(entries)
    names = tree.name_index()
    if "#" in name:
        if name in names:
            return names[name]
        base, _, num = name.rpartition("#")
        if num == "":
            return names.get(base)
        if num == "0" and base in names:
            return names[base]
        return None
    if suffix is not None and suffix >= 0:
        return names.get(f"{name}#{suffix}")
    if name in names:
        return names[name]
    for e in tree.entries:
        if alias_of(e) == name:
            return e.handle
    return None


def name_suffix(name: str) -> int | None:
    """``robot#1`` -> 1; a name without a numeric ``#`` suffix -> None."""
    base, sep, num = name.rpartition("#")
    return int(num) if sep and num.isdigit() else None


def full_path(entries: Iterable[Node] | Tree, handle: int) -> str:
    """``/a/b/c``: the aliases from the root down to ``handle`` (CoppeliaSim's full path)."""
    tree = _tree(entries)
    parts = []
    entry: Any = tree.by_handle.get(handle)
    while entry is not None:
        parts.append(alias_of(entry))
        entry = tree.by_handle.get(entry.parent) if entry.parent is not None else None
    return "/" + "/".join(reversed(parts))


def nearest(entries: Iterable[Node] | Tree, path: str, count: int = 3) -> tuple[str, ...]:
    """The scene's full paths (or names, for an old-style name) closest to ``path``."""
    import difflib

    tree = _tree(entries)
    if is_path(path):
        pool = sorted({full_path(tree, e.handle) for e in tree.entries})
        query = "/" + path.lstrip("./:")
    else:
        pool = sorted({e.name for e in tree.entries} | {alias_of(e) for e in tree.entries})
        query = path
    return tuple(difflib.get_close_matches(query, pool, n=count, cutoff=0.5))
