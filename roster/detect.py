"""Which layout a text roster is written in, decided from its content.

The course has kept its groups in five text layouts since 2019, and a roster arrives with
whatever a given year used:

- ``paired``: one group a line, `group<TAB>id<TAB>account<TAB>id<TAB>account...` (2021, stage 3)
- ``ids``: one group a line, `group<TAB>id<TAB>id...` (2021, stages 1-2)
- ``rows``: one member a line with a group column, `id<TAB>account<TAB>group` under a header
  like `2a / github 帳號 / 組別` (2022); the group column may come first
- ``blocks``: a group label line (`2ag1`, `group 1:`), then its members one a line (2019,
  2023-24); in 2025 a GitHub team list (`Processing team: g1`, then `Login: ..., ID: ...`)
- ``lists``: a Python list of lists of ids, `[['40723104', ...], [...]]` (2020)

Every non-blank line is classed by where its ids are (an id first: a *member* line; a name,
then ids: a *group* line; no id at all: a *label*), and the layout follows from the mix of
classes and, for member lines, from whether one column holds a few repeated short values (the
group numbers). Two more shapes are recognised so they get one clear error rather than a flood:
an id -> account list with no groups (an *alias list*: `--aliases FILE`) and a bare or numbered
list of ids. Fields are tab-separated where a line has a tab, else comma-separated where it has
a comma, else separated by runs of spaces (full-width spaces too).
"""

from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass, field

from .labels import column_role, id_like, is_separator, login_record
from .model import quoted
from .records import Collector, split_mark_words, split_marks

TEXT_LAYOUTS = ("paired", "ids", "rows", "blocks", "lists")
LAYOUTS = ("auto", *TEXT_LAYOUTS)
EXPECTED = (
    "expected one of: one group a line (stage1_ag1<TAB>40823101<TAB>40823102...), one member "
    "a line with a group column (40923101<TAB>a40923101<TAB>1), a group label line then its "
    "ids one a line (2ag1 or group 1: then 40923101...), or a Python list of lists of ids"
)


def split_fields(line: str, marks: frozenset[str] = frozenset()) -> list[str]:
    """A line's fields. Tabs separate fields where the line has one, else commas (an empty
    field keeps its place; trailing empty ones are dropped), else runs of whitespace; with
    whitespace, a mark word (`X 40823151`) or an annotation (`40823122 (退選)`) standing
    alone joins the value beside it."""
    for sep in ("\t", ","):
        if sep in line:
            fields = [f.strip() for f in line.split(sep)]
            while fields and not fields[-1]:
                fields.pop()
            return fields
    out: list[str] = []
    pending: list[str] = []  # mark words waiting for the value after them
    for token in line.split():
        if token in marks:
            if out and not pending and out[-1] not in marks and _is_value(out[-1]):
                out[-1] += " " + token  # `40623121 X`: a mark after the value
            else:
                pending.append(token)
            continue
        if out and not pending and not split_marks(token)[0] and split_marks(token)[1]:
            out[-1] += " " + token  # `40823122 (dropped)`
            continue
        out.append(" ".join([*pending, token]))
        pending = []
    if pending:
        out.append(" ".join(pending))
    return out


def _is_value(token: str) -> bool:
    return bool(split_marks(token)[0])


def clean(value: str, c: Collector) -> str:
    """A field without mark words or annotation symbols, for telling layouts apart."""
    return split_marks(split_mark_words(value, c.mark_words)[0])[0]


@dataclass
class Columns:
    """Where a one-member-a-line file keeps each thing (0-based field indexes)."""

    id: int
    group: int
    account: int | None = None
    ignored: dict[int, str] = field(default_factory=dict)  # index -> why (its header or kind)
    width: int = 0


@dataclass
class Detected:
    """The layout chosen, why (said in an info line), and what the parser needs to know."""

    layout: str  # a TEXT_LAYOUTS name, "accounts" (an alias list) or "none"
    reason: str
    header_line: int = 0
    columns: Columns | None = None
    problem: str = ""  # for "accounts" and "none": the one error to report
    problem_line: int = 1  # ... and the line it is reported at
    spaced: bool = False  # no tabs in the file: group-first lines are split on spaces


@dataclass
class _Line:
    number: int
    fields: list[str]
    kind: str  # "member", "group" or "label"


def classify(lines: list[str], c: Collector) -> list[_Line]:
    """Every data line (not blank, not a `-----` separator) with its fields and class."""
    out = []
    for number, text in enumerate(lines, 1):
        if not text.strip() or is_separator(text):
            continue
        fields = split_fields(text, c.mark_words)
        cleaned = [clean(f, c) for f in fields]
        if (cleaned and id_like(cleaned[0])) or login_record(text):
            kind = "member"
        elif any(id_like(v) for v in cleaned[1:]) or any(
            id_like(t) for v in cleaned[:1] for t in v.split()[1:]
        ):
            kind = "group"
        else:
            kind = "label"
        out.append(_Line(number, fields, kind))
    return out


def detect(lines: list[str], c: Collector, layout: str = "auto") -> Detected:
    """The layout of a text roster: the one asked for, or the one its content shows."""
    spaced = not any("\t" in line for line in lines)
    first = next((line.strip() for line in lines if line.strip()), "")
    if layout == "lists" or (layout == "auto" and first.startswith("[")):
        why = "given" if layout == "lists" else "detected: the file is a Python list of lists"
        return Detected("lists", why)
    data = classify(lines, c)
    if layout in ("paired", "ids") or not data:  # nothing at all: "no groups found"
        return Detected(layout if data else "group-first", "given", spaced=spaced)
    counts = Counter(line.kind for line in data)
    members = [line for line in data if line.kind == "member"]
    groups = [line for line in data if line.kind == "group"]
    if layout == "rows" or (layout == "auto" and members and len(members) > len(groups)):
        found = _rows(data, members, c)
        if found is not None or layout == "rows":
            return found or Detected(
                "none", "given", problem="no column of group numbers or names found"
            )
    if layout == "auto" and groups and len(groups) >= len(members):
        return _group_first(data, groups, spaced, c)
    labels = [line for line in data if line.kind == "label"]
    if layout == "blocks" or (
        labels and members and labels[0].number < members[-1].number and not _is_header(labels)
    ):
        return Detected("blocks", "given" if layout == "blocks" else _blocks_reason(labels))
    return _not_a_roster(data, members, counts)


def _blocks_reason(labels: list[_Line]) -> str:
    shown = ", ".join(repr(" ".join(line.fields)) for line in labels[:3])
    more = ", ..." if len(labels) > 3 else ""
    return f"detected: group label lines ({shown}{more}) each followed by ids"


def _is_header(labels: list[_Line]) -> bool:
    """A single label line that names columns (`學號 / github 帳號`) heads a list, not a group."""
    return len(labels) == 1 and any(column_role(f) in ("id", "account") for f in labels[0].fields)


def _group_first(data: list[_Line], groups: list[_Line], spaced: bool, c: Collector) -> Detected:
    """One group a line (paired or ids, decided by `parse_tsv.choose_layout`), unless the
    group names repeat (one member a line, group first) or count 1, 2, 3 (a numbered list)."""
    names = [clean_name(line.fields[0]) for line in groups]
    if len(groups) >= 4 and len(set(names)) * 2 <= len(groups):
        found = _rows(data, groups, c, group_col=0)
        if found is not None:
            return found
    numbers = [n.rstrip(".") for n in names]
    counting = all(n.isdigit() for n in numbers) and [int(n) for n in numbers] == list(
        range(int(numbers[0]), int(numbers[0]) + len(numbers))
    )
    if len(groups) >= 3 and counting:
        return Detected(
            "none",
            "",
            problem_line=groups[0].number,
            problem=f"no roster layout fits: lines {groups[0].number}-{groups[-1].number} are "
            f"a numbered list of {len(groups)} students, not groups; " + EXPECTED,
        )
    return Detected("group-first", "", spaced=spaced)


def clean_name(value: str) -> str:
    return value.strip().rstrip(":：").strip()


def _header_before(data: list[_Line], first: _Line) -> int:
    """The line of a label heading the data (the last label before `first`), or 0."""
    before = [line for line in data if line.number < first.number and line.kind == "label"]
    return before[-1].number if before else 0


def _rows(
    data: list[_Line], members: list[_Line], c: Collector, group_col: int | None = None
) -> Detected | None:
    """One member a line, if a column holds group numbers or names; else None."""
    width = Counter(len(line.fields) for line in members).most_common(1)[0][0]
    header_line = _header_before(data, members[0])
    header = next((line.fields for line in data if line.number == header_line), [])
    roles = [column_role(f) for f in header] if len(header) == width else []
    if sum(role is not None for role in roles) < 2:  # `group 2:` is a label, not a header
        roles = []
    cols = _columns(members, width, roles, c, group_col)
    if cols is None:
        return None
    named = f"the header row (line {header_line}) and " if roles else ""
    return Detected(
        "rows",
        f"detected from {named}the columns: one member a line, group in column {cols.group + 1}",
        header_line=header_line,
        columns=cols,
    )


def _column(members: list[_Line], index: int, c: Collector) -> list[str]:
    return [clean(line.fields[index], c) for line in members if len(line.fields) > index]


def _columns(
    members: list[_Line], width: int, roles: list, c: Collector, group_col: int | None = None
) -> Columns | None:
    """Which column is the id, the group and the account, from the header's words where it
    names them and otherwise from the values: the group column holds few distinct short
    values that are not ids, repeated down the file (`1`..`7` over 56 lines)."""

    def role(name: str) -> int | None:
        return roles.index(name) if name in roles else None

    if group_col is None:
        group_col = role("group")
    id_col = role("id")
    if id_col is None:
        id_col = next(
            (
                i
                for i in range(width)
                if i != group_col
                and (values := [v for v in _column(members, i, c) if v])
                and sum(map(id_like, values)) * 5 >= len(values) * 4
            ),
            0,
        )
    if group_col is None:
        candidates = []
        for index in range(width):
            values = [v for v in _column(members, index, c) if v]
            if index == id_col or len(values) < 2:
                continue
            distinct = len(set(values))
            if sum(not id_like(v) and len(v) <= 30 for v in values) * 5 >= len(
                values
            ) * 4 and distinct * 2 <= len(values):
                candidates.append((distinct > 1, index))
        if not candidates:
            return None
        group_col = max(candidates)[1]
    account_col = role("account")
    ignored: dict[int, str] = {}
    for index in range(width):
        if index in (id_col, group_col, account_col):
            continue
        values = [v for v in _column(members, index, c) if v]
        if (
            account_col is None
            and roles[index : index + 1] in ([], [None])
            and _account_like(values)
        ):
            account_col = index
            continue
        label = roles[index] if index < len(roles) and roles[index] else "unnamed"
        sample = values[0] if values else ""
        ignored[index] = f"{label}, e.g. {sample!r}" if sample else label
    return Columns(id_col, group_col, account_col, ignored, width)


def _account_like(values: list[str]) -> bool:
    """GitHub-account-like text (ASCII letters, digits, `-`), mostly ids or mostly different
    from line to line (a class column, `2a` on every line, is not an account)."""
    ok = sum(bool(re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]*", v)) for v in values)
    ids = sum(map(id_like, values))
    varied = len(set(values)) * 2 > len(values) or ids * 2 > len(values)
    return bool(values) and ok * 5 >= len(values) * 4 and varied


def _not_a_roster(data: list[_Line], members: list[_Line], counts: Counter) -> Detected:
    """The one error for a file no layout fits, saying what it looks like instead."""
    if members and all(len(line.fields) == 2 for line in members):
        return Detected(
            "accounts",
            "",
            problem_line=members[0].number,
            problem=f"this file is an id -> account list with no groups ({len(members)} "
            "students): use it as aliases (--aliases FILE, or aliases: in the roster's "
            "sitegen.yml entry) for a roster that has the groups",
        )
    if members and all(len(line.fields) == 1 for line in members):
        what = f"a list of {len(members)} student ids with no group labels"
    elif not members and not counts["group"]:
        what = f"{len(data)} line(s) of text with no student id"
    else:
        what = (
            f"{counts['member']} line(s) starting with an id, {counts['group']} starting "
            f"with a name, {counts['label']} without ids, in no order a layout has"
        )
    first = data[0]
    shown = f"line {first.number}: {quoted(' '.join(first.fields)[:60])}"
    return Detected(
        "none",
        "",
        problem=f"no roster layout fits this file ({what}; {shown}); {EXPECTED}",
        problem_line=first.number,
    )
