"""One member a line with a group column: `id<TAB>account<TAB>group` (the course in 2022).

The teacher's own scripts read this file as: skip the header (`2a / github 帳號 / 組別`),
split each line into student id, GitHub account and group number, use the id where the
account is empty, and leave a student with no group number out of the groups ("尚未分組者",
not yet grouped). Members are grouped by the group column, in file order within a group;
groups are ordered by their number or name (natural order: 2 before 10), as the scripts
sorted them. A group written as a bare number `1` is named `group 1` (its slug `group-1`), so
page headings and repository names read as names; a `group_names` rule renames them.

Which column is which comes from `detect` (the header's words, else the values), so the same
parser reads `group<TAB>id<TAB>account` and files with extra columns (a name, a class) too.
"""

from __future__ import annotations

from .detect import Columns, Detected, clean, split_fields
from .labels import group_label, id_like, is_separator, natural_key
from .model import WHOLE_FILE, quoted
from .records import Collector, RawGroup, RawMember, make_member


def group_name(value: str) -> str:
    """The group column's value as a name: `1` -> `group 1`, `2ag1` and `第一組` as written."""
    name = group_label(value)
    return f"group {name}" if name.isdigit() else name


def parse_rows(lines: list[str], c: Collector, found: Detected) -> list[RawGroup]:
    """Raw groups from one-member-a-line text, reporting into `c`."""
    cols = found.columns
    assert cols is not None
    if cols.ignored:
        shown = "; ".join(f"column {i + 1} ({why})" for i, why in sorted(cols.ignored.items()))
        c.info(WHOLE_FILE, "columns", f"not part of the roster, ignored: {shown}")
    _ids_in_ignored_columns(lines, c, cols)
    groups: dict[str, RawGroup] = {}
    ungrouped: list[RawMember] = []
    for lineno, text in enumerate(lines, 1):
        if lineno == found.header_line:
            shown = ", ".join(quoted(f) for f in split_fields(text))
            c.info(lineno, "line", f"header row skipped: {shown}")
            continue
        if not text.strip() or is_separator(text):
            what = "blank line skipped" if not text.strip() else "separator skipped"
            c.info(lineno, "line", what)
            continue
        fields = split_fields(text, c.mark_words)
        _row(fields, lineno, cols, groups, ungrouped, c)
    if ungrouped:
        shown = ", ".join(f"{m.id} (line {m.line})" for m in ungrouped)
        c.warning(
            ungrouped[0].line,
            _where(cols.group, "group"),
            f"{len(ungrouped)} student(s) have no group yet and are not on the roster page: "
            f"{shown}",
        )
    return sorted(groups.values(), key=lambda g: natural_key(g.name))


def _where(index: int | None, what: str) -> str:
    return f"{what} (col {index + 1})" if index is not None else what


def _row(
    fields: list[str],
    lineno: int,
    cols: Columns,
    groups: dict[str, RawGroup],
    ungrouped: list[RawMember],
    c: Collector,
) -> None:
    """One line's member, added to its group (or to `ungrouped`)."""

    def cell(index: int | None) -> str | None:
        return fields[index] if index is not None and index < len(fields) else None

    if len(fields) > cols.width:
        extra = " ".join(fields[cols.width :])
        c.error(
            lineno,
            f"col {cols.width + 1}",
            f"more fields than the roster's {cols.width} columns: {quoted(extra)} not read "
            "(a value with spaces in a space-separated file?)",
        )
    id_raw = cell(cols.id) or ""
    if not id_like(clean(id_raw, c)):
        values = " ".join(fields)
        c.error(lineno, _where(cols.id, "id"), f"line has no student id ({quoted(values)})")
        return
    member = make_member(
        c,
        id_raw,
        cell(cols.account) if cols.account is not None else None,
        lineno,
        _where(cols.id, "id"),
        _where(cols.account, "account"),
        missing_account="no account given" if cols.account is not None else None,
        missing_severity="info",
    )
    if member is None:
        return
    raw_group = cell(cols.group) or ""
    if not raw_group.strip():
        ungrouped.append(member)
        return
    name = group_name(raw_group)
    group = groups.get(name)
    if group is None:
        group = groups[name] = RawGroup(name=name, line=lineno, field=_where(cols.group, "group"))
    group.members.append(member)


def _ids_in_ignored_columns(lines: list[str], c: Collector, cols: Columns) -> None:
    """A student id in a column that is not read would vanish: an error at its line."""
    for lineno, text in enumerate(lines, 1):
        fields = split_fields(text, c.mark_words)
        for index in sorted(cols.ignored):
            if index < len(fields) and id_like(clean(fields[index], c)):
                c.error(
                    lineno,
                    f"col {index + 1}",
                    f"{quoted(fields[index])} looks like a student id in column {index + 1}, "
                    "which is not read (the columns are id, account and group; "
                    "set them with a header row)",
                )
