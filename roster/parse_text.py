"""Text rosters (.txt, .tsv): find the layout (`detect`), then read it with its parser.

A file no layout fits, or an id -> account list read as a roster, gets one error saying what
the file looks like and what was expected, never a line-by-line flood of "group has no
members". The layout chosen is said in an info line and kept in `Collector.layout`.
"""

from __future__ import annotations

from .detect import Detected, clean, clean_name, detect, split_fields
from .labels import id_like
from .model import WHOLE_FILE
from .parse_blocks import parse_blocks
from .parse_lists import parse_lists
from .parse_rows import parse_rows
from .parse_tsv import parse_tsv
from .records import Collector, RawGroup


def parse_text(lines: list[str], c: Collector, layout: str = "auto") -> list[RawGroup]:
    """Raw groups from a text roster in any of the course's layouts, reporting into `c`."""
    found = detect(lines, c, layout)
    if found.layout in ("none", "accounts"):
        c.layout = found.layout
        c.error(found.problem_line, "layout", found.problem)  # one error, not a flood
        return []
    if found.layout in ("group-first", "paired", "ids"):
        if found.spaced:
            lines = _tabbed(lines, c)
        return parse_tsv(lines, c, layout if layout in ("paired", "ids") else "auto")
    c.layout = found.layout
    c.info(WHOLE_FILE, "layout", f"{found.layout} layout ({found.reason})")
    if found.layout == "rows":
        return parse_rows(lines, c, found)
    if found.layout == "blocks":
        return parse_blocks(lines, c)
    return parse_lists(lines, c)


def _tabbed(lines: list[str], c: Collector) -> list[str]:
    """A file with no tab at all, written with spaces (or commas): one group a line becomes
    tab-separated, the group name being the words before the first id (`group 1: 40623108`
    -> `group 1`), so the tab parser reads it with the same checks."""
    out = []
    for line in lines:
        fields = split_fields(line, c.mark_words)
        start = next((i for i, f in enumerate(fields) if id_like(clean(f, c))), len(fields))
        if not line.strip() or start == len(fields):  # blank, or a header: fields as they are
            out.append("\t".join(fields))
            continue
        name = clean_name(" ".join(fields[:start])) if start else ""
        out.append("\t".join([name, *fields[start:]]))
    if any(line.strip() for line in lines):
        c.info(WHOLE_FILE, "file", "no tabs in the file: fields read as separated by spaces")
    return out


__all__ = ["Detected", "parse_text"]
