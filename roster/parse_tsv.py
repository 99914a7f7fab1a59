"""The course's one-group-a-line rosters, in two layouts (`detect` picks these or another).

`paired` (stage 3): `group<TAB>id<TAB>account<TAB>id<TAB>account...`; `ids` (earlier
stages): `group<TAB>id<TAB>id...`, each account being the id unless the corrections give
an alias. The layout is given (`layout=`) or detected from the file: a header row
(`組別<TAB>組員1...` or `group<TAB>member1...`) says which, and without one, a file whose
would-be accounts are mostly *other* students' ids is the ids layout. Reading the ids
layout as paired silently turned every second student into the previous one's account,
so a file declared paired that looks like that is an error, never a guess.

Fields are paired by position, as the teacher's spreadsheet lays them out, so an
empty slot in the middle keeps the members after it aligned (the old script's
`replace('\\t\\t', '')` shifted them). Empty slots, blank lines and spaces are
tolerated and reported; a line whose fields are separated by spaces instead of
tabs is an error rather than a silently mis-read group.
"""

from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass

from .labels import ACCOUNT_LABEL as _ACCOUNT_LABEL
from .labels import GROUP_HEADERS as _HEADER_GROUP
from .labels import MEMBER_LABEL as _HEADER_LABEL
from .labels import id_like
from .model import WHOLE_FILE, quoted
from .records import (
    Collector,
    RawGroup,
    describe_members,
    is_student_id,
    make_member,
    split_mark_words,
    split_marks,
)


def _ranges(numbers: list[int]) -> str:
    """`[1, 2, 3, 7]` -> `1-3, 7` for compact messages."""

    def span(a: int, b: int) -> str:
        return str(a) if a == b else f"{a}-{b}"

    out: list[str] = []
    start = prev = numbers[0]
    for n in numbers[1:]:
        if n == prev + 1:
            prev = n
            continue
        out.append(span(start, prev))
        start = prev = n
    out.append(span(start, prev))
    return ", ".join(out)


def _space_separated(line: str) -> bool:
    """A line with no tab whose later words look like ids was typed with spaces, not tabs."""
    words = line.split()
    return len(words) > 1 and any(is_student_id(split_marks(w)[0]) for w in words[1:])


@dataclass
class Layout:
    """The layout used to read a file, and why (said in an info line)."""

    name: str
    reason: str
    header_line: int = 0


def _clean(value: str, c: Collector) -> str:
    """A field without mark words or annotation symbols, for layout detection only."""
    return split_marks(split_mark_words(value, c.mark_words)[0])[0]


_HEADER_WORD = re.compile(r"組員|成員|組別|分組|學號|帳號|member|account|github", re.IGNORECASE)


def _header(line: str, c: Collector) -> str | None:
    """ "ids" or "paired" if `line` is a header row, else None."""
    fields = [f.strip() for f in line.split("\t")]
    labels = [f for f in fields[1:] if f]
    if not labels or any(id_like(_clean(f, c)) for f in fields):
        return None
    first = fields[0].lower()
    strict = not any(_clean(f, c).isdigit() for f in labels) and (
        first in _HEADER_GROUP or all(_HEADER_LABEL.fullmatch(f) for f in labels)
    )
    # written with spaces, `2a cad2021 member 1 member 2` splits into words: its words say it
    loose = any(_HEADER_WORD.search(f) for f in fields)
    if not (strict or loose):
        return None
    return "paired" if any(_ACCOUNT_LABEL.search(f) for f in labels) else "ids"


def _shape(value: str) -> str:
    return "".join("9" if ch.isdigit() else "a" for ch in value)


def _id_accounts(rows: list[tuple[int, list[str]]], c: Collector) -> tuple[int, int, str, int]:
    """(pairs whose account is another student's id, pairs with both given, the first such
    pair as text, its line)."""
    firsts = [_clean(f[1], c) for _, f in rows if len(f) > 1 and _clean(f[1], c)]
    if not firsts:
        return 0, 0, "", 0
    shape = Counter(_shape(v) for v in firsts).most_common(1)[0][0]
    others = total = example_line = 0
    example = ""
    for lineno, fields in rows:
        for k in range(1, len(fields) - 1, 2):
            sid, acc = _clean(fields[k], c), _clean(fields[k + 1], c)
            if not sid or not acc:
                continue
            total += 1
            if acc != sid and _shape(acc) == shape and is_student_id(acc):
                others += 1
                if not example:
                    example = f"{acc} in the account column after {sid}"
                    example_line = lineno
    return others, total, example, example_line


def _all_ids(rows: list[tuple[int, list[str]]], c: Collector) -> bool:
    """Every non-empty field after the group name is a student id (marks aside)."""
    return all(
        is_student_id(_clean(f, c)) for _, fields in rows for f in fields[1:] if _clean(f, c)
    )


def choose_layout(lines: list[str], c: Collector, layout: str) -> Layout:
    """Decide the layout from `layout` and the file; a paired file full of ids is an error."""
    header_line = 0
    header_kind = None
    for lineno, line in enumerate(lines, 1):
        if line.strip():
            header_kind = _header(line, c)
            header_line = lineno if header_kind else 0
            break
    rows = [
        (n, line.split("\t"))
        for n, line in enumerate(lines, 1)
        if line.strip() and n != header_line and "\t" in line
    ]
    others, total, example, example_line = _id_accounts(rows, c)
    mostly_ids = total >= 2 and others * 2 > total
    if layout == "ids":
        return Layout("ids", "given", header_line)
    if layout == "auto" and header_kind == "ids":
        return Layout("ids", f"detected from the header row (line {header_line})", header_line)
    if layout == "auto" and header_kind is None and mostly_ids and _all_ids(rows, c):
        return Layout(
            "ids",
            f"detected: {others} of {total} would-be accounts are other students' ids",
            header_line,
        )
    single = bool(rows) and all(len([f for f in r[1][1:] if f.strip()]) == 1 for r in rows)
    if layout == "auto" and header_kind is None and single and _all_ids(rows, c):
        return Layout("ids", "detected: every line holds a single id", header_line)
    if mostly_ids:
        why = "declared paired" if layout == "paired" else "read as paired"
        if header_kind == "paired":
            why = f"the header row (line {header_line}) names account columns"
        c.error(
            example_line,
            "layout",
            f"{why}, but {others} of {total} accounts are other students' ids "
            f"(first here: {example}); "
            "if the file lists only ids, set layout: ids (sitegen.yml) or --layout ids",
        )
    reason = "given" if layout == "paired" else "detected"
    if header_kind == "paired":
        reason = f"detected from the header row (line {header_line})"
    return Layout("paired", reason, header_line)


def parse_tsv(lines: list[str], c: Collector, layout: str = "auto") -> list[RawGroup]:
    """Parse TSV lines into raw groups, reporting into `c` (and the layout into `c.layout`)."""
    chosen = choose_layout(lines, c, layout)
    c.layout = chosen.name
    c.info(WHOLE_FILE, "layout", f"{chosen.name} layout ({chosen.reason})")
    groups: list[RawGroup] = []
    for lineno, line in enumerate(lines, 1):
        if lineno == chosen.header_line:
            shown = ", ".join(quoted(f.strip()) for f in line.split("\t") if f.strip())
            c.info(lineno, "line", f"header row skipped: {shown}")
            continue
        if not line.strip():
            what = "blank line skipped" if not line else "line of only whitespace skipped"
            c.info(lineno, "line", what)
            continue
        fields = line.split("\t")
        if len(fields) == 1 and _space_separated(line):
            c.error(
                lineno,
                "col 1",
                f"no tab between fields in {quoted(line.strip())}; "
                "the roster must be tab-separated",
            )
            continue
        name_raw = fields[0]
        name = name_raw.strip()
        if name != name_raw:
            c.trimmed(lineno, "group name (col 1)")
        group = RawGroup(name=name, line=lineno, field="group name (col 1)")
        empty: list[int] = []
        if chosen.name == "ids":
            _ids_members(c, group, fields, lineno, empty)
        for k in range(1, len(fields) if chosen.name == "paired" else 1, 2):
            slot = (k + 1) // 2
            id_raw = fields[k]
            account_raw = fields[k + 1] if k + 1 < len(fields) else None
            if not id_raw.strip() and not (account_raw or "").strip():
                empty.append(slot)
                continue
            member = make_member(
                c,
                id_raw,
                account_raw,
                lineno,
                f"member {slot} id (col {k + 1})",
                f"member {slot} account (col {k + 2})",
                missing_account="odd trailing id with no account"
                if account_raw is None
                else "empty account",
            )
            if member is not None:
                group.members.append(member)
        if empty:
            c.info(lineno, "line", f"empty member slot(s) {_ranges(empty)} skipped")
        if not name:
            ids = describe_members(group.members)
            c.error(
                lineno, "group name (col 1)", f"group name is empty (members on this line: {ids})"
            )
            continue
        groups.append(group)
    return groups


def _ids_members(
    c: Collector, group: RawGroup, fields: list[str], lineno: int, empty: list[int]
) -> None:
    """Members of an ids-layout line: every field is an id whose account is the id."""
    for k in range(1, len(fields)):
        if not fields[k].strip():
            empty.append(k)
            continue
        where = f"member {k} id (col {k + 1})"
        member = make_member(c, fields[k], None, lineno, where, where, missing_account=None)
        if member is not None:
            group.members.append(member)
