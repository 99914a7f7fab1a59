"""Reading YAML as a node tree so every value keeps its line number.

`yaml.safe_load` throws line numbers away and turns `0123` or `40823131` into
ints; composing instead keeps each scalar's exact text and `start_mark`, which
is what error messages and "correction applied at line N" reports need. The
tree is also checked for things plain loading hides: duplicate keys (the later
one would silently win) and anchors/aliases (which can blow up exponentially).
"""

from __future__ import annotations

from collections.abc import Iterator

import yaml

from .records import Collector

_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

Node = yaml.Node
ROOT = "top level"  # the `where` of the document's root mapping


def line_of(node: Node) -> int:
    """1-based line where a node starts."""
    return node.start_mark.line + 1


def compose(text: str, c: Collector) -> Node | None:
    """Compose one YAML document, reporting syntax errors at their line."""
    try:
        return yaml.compose(text, Loader=_Loader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark is not None else 1
        where = f"char {mark.column + 1}" if mark is not None else "file"
        c.error(line, where, f"YAML syntax error: {exc.problem or exc.context or exc}")
    except yaml.YAMLError as exc:
        c.error(1, "file", f"YAML error: {exc}")
    return None


class Walker:
    """Type-checked access to a composed tree, reporting problems into a Collector."""

    def __init__(self, c: Collector) -> None:
        self.c = c
        self._seen: set[int] = set()

    def _visit(self, node: Node, where: str) -> bool:
        """False (with an error) if this node object was reached before: an alias."""
        if id(node) in self._seen:
            self.c.error(line_of(node), where, "YAML anchors/aliases are not supported here")
            return False
        self._seen.add(id(node))
        return True

    def mapping(self, node: Node, where: str) -> Iterator[tuple[str, Node, Node]]:
        """Yield (key text, key node, value node), reporting non-mappings and duplicate keys."""
        if not isinstance(node, yaml.MappingNode):
            self.c.error(line_of(node), where, f"expected a mapping, got {describe(node)}")
            return
        if not self._visit(node, where):
            return
        seen: dict[str, int] = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, yaml.ScalarNode):
                self.c.error(
                    line_of(key_node), where, f"keys must be plain text, got {describe(key_node)}"
                )
                continue
            key = key_node.value
            if key in seen:
                self.c.error(
                    line_of(key_node),
                    f"{where}.{key}" if where != ROOT else key,
                    f"duplicate key {key!r} (first at line {seen[key]})",
                )
                continue
            seen[key] = line_of(key_node)
            yield key, key_node, value_node

    def sequence(self, node: Node, where: str) -> list[Node]:
        """The items of a sequence node, or [] with an error."""
        if not isinstance(node, yaml.SequenceNode):
            self.c.error(line_of(node), where, f"expected a list, got {describe(node)}")
            return []
        if not self._visit(node, where):
            return []
        return list(node.value)

    def scalar(self, node: Node, where: str, allow_empty: bool = False) -> str | None:
        """The stripped text of a scalar node, or None with an error."""
        if not isinstance(node, yaml.ScalarNode):
            self.c.error(line_of(node), where, f"expected a text value, got {describe(node)}")
            return None
        value = node.value.strip()
        if not value and not allow_empty:
            self.c.error(line_of(node), where, "value is empty")
            return None
        return value


def describe(node: Node) -> str:
    """A short human name for a node's kind, for type errors."""
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return "a list"
    if isinstance(node, yaml.ScalarNode):
        return f"the text {node.value!r}" if node.value else "an empty value"
    return type(node).__name__
