"""The one way sitegen reads YAML: bounded, safe, and with line numbers kept.

Front matter, ``sitegen.yml`` and roster corrections all come through :func:`compose`. It
composes a node tree (each node keeps its ``start_mark``, so errors can name a line) and first
checks the document against limits, because a few lines of YAML can otherwise ask for
gigabytes: anchors and aliases let ``a: &a [x, x]``, ``b: &b [*a, *a]``, ... double at every
line (the "billion laughs" document), and deep nesting can exhaust the stack. The limits:

- ``max_bytes``: the text's size in UTF-8 bytes;
- ``max_aliases``: how many ``*alias`` references the document may hold;
- ``max_values``: how many values the document holds once every alias is expanded;
- ``max_depth``: how deeply lists and mappings may nest.

Breaking one raises :class:`YamlError` naming the file and line; so does a syntax error.
"""

from __future__ import annotations

import reprlib
from typing import Any

import yaml

from located.diagnostics import Diagnostic, LocatedError

Node = yaml.Node
_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

MAX_BYTES = 1 << 20  # 1 MiB: far above any settings file or front matter
MAX_ALIASES = 100
MAX_VALUES = 100_000
MAX_DEPTH = 64


class YamlError(LocatedError):
    """A YAML document that is malformed or breaks a limit; ``line`` is 1-based in the file.

    A :class:`~located.diagnostics.LocatedError`, so a caller that reports located problems
    one way (``except LocatedError``) needs no YAML case; ``column`` is set for syntax errors."""

    def __init__(self, file: str, line: int | None, message: str, column: int | None = None):
        super().__init__(Diagnostic(file, line, "", message, column=column))

    @property
    def column(self) -> int | None:
        return self.diagnostic.column


def line_of(node: Node, first_line: int = 1) -> int:
    """1-based file line where ``node`` starts (``first_line``: where the YAML text starts)."""
    return node.start_mark.line + first_line


def compose(
    text: str,
    file: str = "<yaml>",
    *,
    first_line: int = 1,
    max_bytes: int = MAX_BYTES,
    max_aliases: int = MAX_ALIASES,
    max_values: int = MAX_VALUES,
    max_depth: int = MAX_DEPTH,
) -> Node | None:
    """Compose one YAML document within the limits; None for an empty document."""
    size = len(text.encode("utf-8", "surrogatepass"))
    if size > max_bytes:
        raise YamlError(file, None, f"YAML document is {size} bytes; the limit is {max_bytes}")
    try:
        _check_events(text, file, first_line, max_aliases, max_depth)
        node = yaml.compose(text, Loader=_Loader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + first_line if mark is not None else None
        column = mark.column + 1 if mark is not None else None
        problem = exc.problem or exc.context or str(exc)
        raise YamlError(file, line, f"YAML syntax error: {problem}", column) from None
    except yaml.YAMLError as exc:
        raise YamlError(file, None, f"YAML error: {exc}") from None
    if node is not None:
        _check_expanded_size(node, file, first_line, max_values)
    return node


def _check_events(text: str, file: str, first_line: int, max_aliases: int, max_depth: int) -> None:
    """One linear pass over the parser's events: count aliases, track nesting."""
    aliases = depth = 0
    for event in yaml.parse(text, Loader=_Loader):
        if isinstance(event, yaml.AliasEvent):
            aliases += 1
            if aliases > max_aliases:
                raise YamlError(
                    file,
                    event.start_mark.line + first_line,
                    f"more than {max_aliases} YAML aliases (*name); the limit guards against "
                    "documents that expand to gigabytes",
                )
        elif isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent)):
            depth += 1
            if depth > max_depth:
                raise YamlError(
                    file,
                    event.start_mark.line + first_line,
                    f"lists and mappings nest more than {max_depth} levels deep",
                )
        elif isinstance(event, (yaml.SequenceEndEvent, yaml.MappingEndEvent)):
            depth -= 1


def _check_expanded_size(root: Node, file: str, first_line: int, max_values: int) -> None:
    """Count the values the tree holds with aliases expanded (shared nodes counted each time).

    Children are sized before their parents (an explicit stack, no recursion), and each
    shared node is sized once, so this costs time linear in the composed tree, not in the
    expansion it measures."""
    sizes: dict[int, int] = {}
    stack: list[tuple[Node, bool]] = [(root, False)]
    while stack:
        node, ready = stack.pop()
        if id(node) in sizes:
            continue
        children = _children(node)
        if not ready and children:
            stack.append((node, True))
            stack.extend((child, False) for child in children if id(child) not in sizes)
            continue
        total = 1 + sum(sizes.get(id(child), 1) for child in children)
        sizes[id(node)] = total
        if total > max_values:
            raise YamlError(
                file,
                line_of(node, first_line),
                f"YAML expands to more than {max_values} values (aliases repeat what they "
                "name); write the values out or shorten the document",
            )


def _children(node: Node) -> list[Node]:
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    if isinstance(node, yaml.MappingNode):
        return [part for pair in node.value for part in pair]
    return []


def to_python(node: Node | None) -> Any:
    """Plain Python values (dict, list, str, int, float, bool, None, date) for a composed node.

    Only call this on nodes :func:`compose` returned: it has checked the limits."""
    if node is None:
        return None
    return yaml.constructor.SafeConstructor().construct_document(node)


def load(text: str, file: str = "<yaml>", **limits: Any) -> Any:
    """``compose`` then ``to_python``: the bounded replacement for ``yaml.safe_load``."""
    return to_python(compose(text, file, **limits))


def short_repr(value: Any, limit: int = 60) -> str:
    """``repr`` cut to ``limit`` characters, for error messages: a wrong value may be huge."""
    r = reprlib.Repr()
    r.maxlist = r.maxdict = r.maxtuple = r.maxset = 4
    r.maxstring = r.maxother = limit
    text = r.repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."
