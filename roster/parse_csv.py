"""CSV rosters: a header `group,id,account`, then one member per row.

This is the format a spreadsheet or LMS export produces most easily. Rows of a
group need not be adjacent; groups keep the order of their first row. Optional
columns: `leader` (a truthy cell marks the group leader) and `notes`. The link
columns written by `roster.emit.to_csv` are recognised and ignored, so its
output can be read back. An export's own headers are read by their words
(`學號,姓名,GitHub帳號,組別`: `roster.labels`); its other columns (names, classes,
e-mails) are listed once as ignored, and up to three title rows above the header are
skipped with a note. A bare group number is named `group N`, as in text rosters.
"""

from __future__ import annotations

import csv

from .labels import column_role
from .model import quoted
from .parse_rows import group_name as group_name_of
from .records import Collector, RawGroup, make_member

REQUIRED = ("group", "id")
OPTIONAL = ("account", "leader", "notes")
DERIVED = ("slug", "repo_url", "site_url", "group_repo_url", "group_site_url")
TRUE_CELLS = {"1", "y", "yes", "true", "x", "leader", "*", "✓"}
FALSE_CELLS = {"", "0", "n", "no", "false", "-"}
MAX_TITLE_ROWS = 3  # rows an export may put above its header


def _roles(row: list[str]) -> dict[str, int]:
    """Column name -> index, by exact name first, then by the course's words for it
    (`學號` id, `GitHub帳號` account, `組別` group, `備註` notes; `roster.labels`)."""
    columns: dict[str, int] = {}
    for i, cell in enumerate(row):
        name = cell.strip().lower()
        if name in REQUIRED or name in OPTIONAL or name in DERIVED:
            columns.setdefault(name, i)
    for i, cell in enumerate(row):
        role = column_role(cell)
        if role in ("id", "account", "group", "notes") and i not in columns.values():
            columns.setdefault(role, i)
    return columns


def _header(row: list[str], lineno: int, c: Collector) -> dict[str, int] | None:
    """Map known column names to indexes, or report why the header is unusable."""
    columns = _roles(row)
    seen: dict[str, int] = {}
    ignored: list[str] = []
    for i, cell in enumerate(row):
        name = cell.strip().lower()
        where = f"header (col {i + 1})"
        if name in seen and name in columns:
            c.error(lineno, where, f"column {quoted(name)} appears twice")
            return None
        seen[name] = i
        if name in DERIVED:
            c.info(lineno, where, f"column {quoted(name)} is derived from the roster and ignored")
        elif i not in columns.values():
            ignored.append(f"{quoted(cell.strip())} (col {i + 1})")
    if ignored:  # a spreadsheet export's names, classes, e-mails: one line for all of them
        c.info(lineno, "header", f"columns not part of the roster, ignored: {', '.join(ignored)}")
    missing = [name for name in REQUIRED if name not in columns]
    if missing:
        c.error(
            lineno,
            "header",
            f"missing column(s) {', '.join(missing)}; the first row must be a header "
            f"with columns group,id,account (got {quoted(','.join(row))})",
        )
        return None
    if "account" not in columns:
        c.warning(lineno, "header", "no account column; every account defaults to the student id")
    return columns


def parse_csv(lines: list[str], c: Collector) -> list[RawGroup]:
    """Parse CSV lines into raw groups, reporting into `c`."""
    reader = csv.reader(line + "\n" for line in lines)
    groups: dict[str, RawGroup] = {}
    columns: dict[str, int] | None = None
    start = 0
    titles = 0  # rows above the header (an export's title), skipped with a note
    title_rows: list[tuple[int, list[str]]] = []
    try:
        for row in reader:
            lineno = start + 1
            start = reader.line_num
            if not any(cell.strip() for cell in row):
                if columns is not None or row:
                    c.info(lineno, "line", "blank row skipped")
                continue
            if columns is None:
                if titles < MAX_TITLE_ROWS and not all(n in _roles(row) for n in REQUIRED):
                    titles += 1
                    title_rows.append((lineno, row))
                    continue
                columns = _header(row, lineno, c)
                if columns is None:
                    rest = sum(1 for r in reader if any(cell.strip() for cell in r))
                    c.error(
                        lineno, "header", f"file not read: {rest + 1} row(s) including this one"
                    )
                    return []
                continue
            _row(row, lineno, columns, groups, c)
    except csv.Error as exc:
        c.error(start + 1, "line", f"CSV syntax error: {exc}")
    if columns is None and title_rows:  # no header anywhere: the first row was meant as one
        lineno, row = title_rows[0]
        _header(row, lineno, c)
        c.error(lineno, "header", f"file not read: {len(title_rows)} row(s) including this one")
    elif columns is None:
        c.error(1, "header", "empty file: expected a header with columns group,id,account")
    else:
        for lineno, row in title_rows:
            c.info(lineno, "line", f"title row above the header skipped: {quoted(','.join(row))}")
    return list(groups.values())


def _cell(row: list[str], columns: dict[str, int], name: str) -> str:
    i = columns.get(name)
    return row[i] if i is not None and i < len(row) else ""


def _row(
    row: list[str], lineno: int, columns: dict[str, int], groups: dict[str, RawGroup], c: Collector
) -> None:
    """Add one CSV row's member to its group."""
    width = max(columns.values()) + 1
    known = set(columns.values())
    if len(row) > width and any(cell.strip() for cell in row[width:]):
        extra = ",".join(row[width:])
        c.error(
            lineno,
            f"col {width + 1}",
            f"row has more cells than the header: {quoted(extra)} not read",
        )
    col = {name: f"{name} (col {i + 1})" for name, i in columns.items()}
    group_name = _cell(row, columns, "group")
    if group_name != group_name.strip():
        c.trimmed(lineno, col["group"])
    group_name = group_name.strip()
    account_raw = _cell(row, columns, "account")
    member = make_member(
        c,
        _cell(row, columns, "id"),
        account_raw,
        lineno,
        col["id"],
        col.get("account", "account"),
        # Without an account column the header warning already said it once.
        missing_account="empty account" if "account" in columns else None,
        missing_severity="info",  # the course's lists: not every student has an account yet
    )
    if member is None:
        if not _cell(row, columns, "id").strip() and not account_raw.strip():
            values = ",".join(cell for i, cell in enumerate(row) if i in known and cell.strip())
            c.error(lineno, col["id"], f"row has no student id ({quoted(values)})")
        return
    # `to_csv` joins several notes with "; "; split them back.
    member.notes += tuple(n.strip() for n in _cell(row, columns, "notes").split(";") if n.strip())
    if not group_name:
        c.error(lineno, col["group"], f"group name is empty for member {member.id}")
        return
    group_name = group_name_of(group_name)
    group = groups.get(group_name)
    if group is None:
        group = groups[group_name] = RawGroup(name=group_name, line=lineno, field=col["group"])
    group.members.append(member)
    leader = _cell(row, columns, "leader").strip().lower()
    if leader in TRUE_CELLS:
        if group.leader is not None and group.leader != member.id:
            c.error(
                lineno,
                col["leader"],
                f"group {quoted(group_name)} already has leader {group.leader} "
                f"(line {group.leader_line})",
            )
        else:
            group.leader = member.id
            group.leader_line = lineno
            group.leader_field = col["leader"]
            group.leader_file = c.file
    elif leader not in FALSE_CELLS:
        c.error(lineno, col["leader"], f"leader cell {quoted(leader)} is not yes/no")
