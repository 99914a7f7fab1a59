"""Finding an object by name or by CoppeliaSim 4.x object path, over a World's object tree.

Accepted forms (what legacy and ZeroMQ scripts pass):
- an old-style name, exactly: ``leftMotor``, ``leftMotor#0``; ``name#`` means ``name``, and
  ``name#0`` falls back to ``name`` when no object has the suffix (the legacy client's habit);
- an absolute path ``/robot/joint``: each part is an alias (the name without ``#`` suffix when
  the object has no alias); a part matches a child first, else any descendant (the first one in
  handle order); ``*`` matches any object; ``/robot/joint[1]`` or ``{1}`` picks the second match;
- a relative path ``./child`` (or ``./a/b``) from the ``relative_to`` handle;
- a bare alias, when exactly one object carries it.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Protocol

_PART = re.compile(r"^(?P<label>.*?)(?:[\[{](?P<index>\d+)[\]}])?$")


class Entry(Protocol):
    handle: int
    name: str
    alias: str
    parent: int | None


def label(entry: Entry) -> str:
    return entry.alias or entry.name.split("#")[0]


def resolve(entries: Sequence[Entry], query: str, relative_to: int | None = None) -> int | None:
    by_name = {e.name: e.handle for e in entries}
    if query in by_name:
        return by_name[query]
    if query.startswith(("/", "./")):
        return _walk(entries, query, relative_to)
    if "#" in query:
        base, _, suffix = query.rpartition("#")
        if suffix in ("", "0") and base in by_name:
            return by_name[base]
        return None
    found = [e.handle for e in entries if e.alias == query]
    return found[0] if len(found) == 1 else None


def _walk(entries: Sequence[Entry], query: str, relative_to: int | None) -> int | None:
    if query.startswith("./"):
        if relative_to is None:
            return None
        scope: list[int | None] = [relative_to]
        parts = query[2:].split("/")
    else:
        scope = [None]
        parts = query[1:].split("/")
    if not parts or any(part == "" for part in parts):
        return None
    children: dict[int | None, list[Entry]] = {}
    for e in entries:
        children.setdefault(e.parent, []).append(e)
    matches: list[Entry] = []
    for part in parts:
        m = _PART.match(part)
        want, index = (m.group("label"), m.group("index")) if m else (part, None)
        matches = _matching(children, scope, want)
        if index is not None:
            n = int(index)
            matches = matches[n : n + 1]
        if not matches:
            return None
        scope = [e.handle for e in matches]
    return matches[0].handle


def _matching(
    children: dict[int | None, list[Entry]], scope: list[int | None], want: str
) -> list[Entry]:
    def ok(e: Entry) -> bool:
        return want == "*" or label(e) == want or e.name == want

    direct = [e for s in scope for e in children.get(s, []) if ok(e)]
    if direct:
        return direct
    found: list[Entry] = []
    queue = [e for s in scope for e in children.get(s, [])]
    while queue:
        e = queue.pop(0)
        if ok(e):
            found.append(e)
        queue.extend(children.get(e.handle, []))
    return found
