"""The course's tab-separated roster: `group<TAB>id<TAB>account<TAB>id<TAB>account...`.

Fields are paired by position, as the teacher's spreadsheet lays them out, so an
empty slot in the middle keeps the members after it aligned (the old script's
`replace('\\t\\t', '')` shifted them). Empty slots, blank lines and spaces are
tolerated and reported; a line whose fields are separated by spaces instead of
tabs is an error rather than a silently mis-read group.
"""

from __future__ import annotations

from .model import quoted
from .records import Collector, RawGroup, describe_members, is_student_id, make_member, split_marks


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


def parse_tsv(lines: list[str], c: Collector) -> list[RawGroup]:
    """Parse TSV lines into raw groups, reporting into `c`."""
    groups: list[RawGroup] = []
    for lineno, line in enumerate(lines, 1):
        if not line.strip():
            what = "blank line skipped" if not line else "line of only whitespace skipped"
            c.info(lineno, "line", what)
            continue
        fields = line.split("\t")
        if len(fields) == 1 and _space_separated(line):
            c.error(
                lineno,
                "col 1",
                f"no tab between fields in {quoted(line.strip())}; the roster must be tab-separated",
            )
            continue
        name_raw = fields[0]
        name = name_raw.strip()
        if name != name_raw:
            c.trimmed(lineno, "group name (col 1)")
        group = RawGroup(name=name, line=lineno, field="group name (col 1)")
        empty: list[int] = []
        for k in range(1, len(fields), 2):
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
