"""Walking a composed YAML tree with line numbers: the one checker for settings and rosters.

``yaml.safe_load`` throws line numbers away (and turns ``0123`` into 83); the readers of
``sitegen.yml`` and of roster and corrections files compose a node tree instead
(:func:`located.yaml.compose`) and walk it with a :class:`Walker`, which checks shapes and
types and records every problem as a :class:`~located.diagnostics.Diagnostic` at the node's
line, so one run reports everything wrong in the file. What it reports the same way for all:
a value of the wrong kind, a duplicate key (YAML would silently keep the later one), a key
that is not allowed, and (when asked) anchors and aliases.
"""

from __future__ import annotations

from collections.abc import Collection, Iterator
from typing import Any

import yaml

from located.diagnostics import Diagnostic, Severity
from located.yaml import short_repr, to_python

Node = yaml.Node
ROOT = "top level"  # the ``where`` of the document's root mapping

KINDS = {
    "str": "a string",
    "int": "a whole number",
    "num": "a number",
    "bool": "true or false",
}


def line_of(node: Node, first_line: int = 1) -> int:
    """1-based file line where ``node`` starts (``first_line``: where the YAML text starts)."""
    return node.start_mark.line + first_line


def child(where: str, key: str) -> str:
    """The key path of ``key`` inside ``where`` (``sims.clips``; plain ``key`` at the root)."""
    return f"{where}.{key}" if where and where != ROOT else key


def describe(node: Node) -> str:
    """A short human name for a node's kind, for type errors."""
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return "a list"
    if isinstance(node, yaml.ScalarNode):
        return f"the text {short_repr(node.value)}" if node.value else "an empty value"
    return type(node).__name__


def _is_kind(value: Any, kind: str) -> bool:
    if kind == "str":
        return isinstance(value, str)
    if kind == "bool":
        return isinstance(value, bool)
    number = (int,) if kind == "int" else (int, float)
    return isinstance(value, number) and not isinstance(value, bool)


class Walker:
    """Checked access to a composed tree; problems go to ``problems`` (a list it may share).

    ``aliases=False`` makes a node reached twice (``*alias``) an error: rosters refuse them
    because a shared node would count one student twice."""

    def __init__(
        self,
        file: str,
        problems: list[Diagnostic] | None = None,
        *,
        first_line: int = 1,
        aliases: bool = True,
    ) -> None:
        self.file = file
        self.problems: list[Diagnostic] = [] if problems is None else problems
        self.first_line = first_line
        self.aliases = aliases
        self._seen: set[int] = set()

    def line(self, node: Node | None) -> int | None:
        return None if node is None else line_of(node, self.first_line)

    def fail(
        self, node: Node | None, where: str, message: str, severity: Severity = "error"
    ) -> None:
        """Record a problem at ``node``'s line (the whole file when ``node`` is None)."""
        self.problems.append(Diagnostic(self.file, self.line(node), where, message, severity))

    def _visit(self, node: Node, where: str) -> bool:
        """False (with an error) when aliases are refused and this node was reached before."""
        if self.aliases:
            return True
        if id(node) in self._seen:
            self.fail(node, where, "YAML anchors/aliases are not supported here")
            return False
        self._seen.add(id(node))
        return True

    def mapping(
        self, node: Node, where: str, allowed: Collection[str] | None = None
    ) -> Iterator[tuple[str, Node, Node]]:
        """Yield (key, key node, value node); report non-mappings, non-text keys, duplicate
        keys and (when ``allowed`` is given) unknown keys, skipping those entries."""
        if not isinstance(node, yaml.MappingNode):
            self.fail(node, where, f"expected a mapping, got {describe(node)}")
            return
        if not self._visit(node, where):
            return
        seen: dict[str, int | None] = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, yaml.ScalarNode):
                self.fail(key_node, where, f"keys must be plain text, got {describe(key_node)}")
                continue
            key = key_node.value
            if key in seen:
                message = f"duplicate key {key!r} (first at line {seen[key]})"
                self.fail(key_node, child(where, key), message)
                continue
            seen[key] = self.line(key_node)
            if allowed is not None and key not in allowed:
                names = ", ".join(sorted(allowed))
                message = f"unknown key {key!r} (expected one of: {names})"
                self.fail(key_node, child(where, key), message)
                continue
            yield key, key_node, value_node

    def keys(self, node: Node, where: str, allowed: Collection[str]) -> dict[str, Node]:
        """The checked mapping as ``{key: value node}``."""
        return {key: value for key, _, value in self.mapping(node, where, allowed)}

    def sequence(self, node: Node, where: str) -> list[Node]:
        """The items of a sequence node, or [] with an error."""
        if not isinstance(node, yaml.SequenceNode):
            self.fail(node, where, f"expected a list, got {describe(node)}")
            return []
        if not self._visit(node, where):
            return []
        return list(node.value)

    def text(self, node: Node, where: str, allow_empty: bool = False) -> str | None:
        """A scalar's exact text, stripped (``0123`` stays ``0123``), or None with an error."""
        if not isinstance(node, yaml.ScalarNode):
            self.fail(node, where, f"expected a text value, got {describe(node)}")
            return None
        value = node.value.strip()
        if not value and not allow_empty:
            self.fail(node, where, "value is empty")
            return None
        return value

    def value(self, node: Node, where: str, kind: str) -> Any:
        """A scalar as YAML types it, checked to be of ``kind`` (see :data:`KINDS`), or None
        with an error."""
        value = to_python(node)
        if not _is_kind(value, kind):
            self.fail(node, where, f"must be {KINDS[kind]}, got {short_repr(value)}")
            return None
        return value
