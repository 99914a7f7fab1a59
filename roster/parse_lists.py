"""A Python list of lists of ids: `[['40723104', '40723107'], ['40623143', ...]]` (2020).

The 2020 grouping script printed its groups this way, and the course's other scripts read the
file back with `ast.literal_eval` and named the groups `group 1`, `group 2`, ... by position.
The text is read with a small tokenizer of our own rather than `ast` so that every id keeps its
line and column for messages, and anything that is not a list of lists of strings or numbers is
an error naming where it is (`ast` would only say "malformed node").
"""

from __future__ import annotations

import re

from .model import quoted
from .records import Collector, RawGroup, make_member

_TOKEN = re.compile(r"""\s+|\[|\]|,|'[^'\n]*'|"[^"\n]*"|[^\s\[\],'"]+""")


def parse_lists(lines: list[str], c: Collector) -> list[RawGroup]:
    """Raw groups from a list of lists, reporting into `c`."""
    groups: list[RawGroup] = []
    depth = 0
    current: RawGroup | None = None
    expect_value = True
    for lineno, text in enumerate(lines, 1):
        pos = 0
        while pos < len(text):
            m = _TOKEN.match(text, pos)
            assert m is not None  # the last alternative matches any other character run
            token, col = m.group(), pos + 1
            pos = m.end()
            if token.isspace() or token == ",":
                expect_value = True
                continue
            if token == "[":
                depth += 1
                if depth == 2:
                    current = RawGroup(f"group {len(groups) + 1}", lineno, f"list (col {col})")
                    groups.append(current)
                elif depth > 2:
                    c.error(lineno, f"col {col}", "lists nested more than two deep")
                    return groups
                continue
            if token == "]":
                depth -= 1
                if depth < 0:
                    c.error(lineno, f"col {col}", "']' without its '['")
                    return groups
                current = None if depth < 2 else current
                continue
            if depth != 2 or current is None or not expect_value:
                c.error(
                    lineno,
                    f"col {col}",
                    f"{quoted(token)} is not inside a group's list "
                    "(expected [['id', 'id', ...], [...]])",
                )
                continue
            value = token[1:-1] if token[0] in "'\"" else token
            member = make_member(
                c, value, None, lineno, f"id (col {col})", f"id (col {col})", missing_account=None
            )
            if member is not None:
                current.members.append(member)
            expect_value = False
    if depth:
        c.error(len(lines), "end", f"{depth} list(s) not closed with ']'")
    return groups
