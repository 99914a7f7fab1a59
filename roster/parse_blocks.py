"""A group label line, then the group's members one a line (the course in 2019 and 2023-24).

    2ag6                      共有 55 位學員
    40923118                  --------------------
    40923120                  group 1:
    2ag5
    40923123                  40623108
                              40623122

The teacher's script (`gen_grp_html.py`) takes every line naming the class (`2ag1`) as a
group title and the lines after it, up to the next title, as that group's student ids;
the 2019 grouping program printed `group N:` over each group, separated by dashes. So: a
line without an id is the label of the group that follows (a trailing `:` dropped); member
lines hold an id, optionally its account (`40923118<TAB>a40923118`) and marks. Groups are
ordered by label (natural order), as the script sorted its titles; members keep file order.

Label lines before the first group's label (a title, `共有 55 位學員`) are reported and
skipped; an id before any label is an error, never a silently dropped student.
"""

from __future__ import annotations

import re

from .detect import clean, split_fields
from .labels import group_label, id_in_login, id_like, is_separator, login_record, natural_key
from .model import quoted
from .records import Collector, RawGroup, RawMember, make_member
from .repo_links import is_safe


def parse_blocks(lines: list[str], c: Collector) -> list[RawGroup]:
    """Raw groups from label-then-members text, reporting into `c`."""
    data = [
        (n, split_fields(text, c.mark_words))
        for n, text in enumerate(lines, 1)
        if text.strip() and not is_separator(text)
    ]
    first_member = next((i for i, (_, f) in enumerate(data) if _is_member(f, c)), len(data))
    groups: list[RawGroup] = []
    current: RawGroup | None = None
    skipped = 0
    for lineno, text in enumerate(lines, 1):
        if not text.strip():
            c.info(lineno, "line", "blank line skipped")
            continue
        if is_separator(text):
            skipped += 1
            continue
        fields = split_fields(text, c.mark_words)
        login = login_record(text)
        if login is not None and current is not None:
            _login_member(c, current, login, lineno)
            continue
        if not _is_member(fields, c):
            position = next(i for i, (n, _) in enumerate(data) if n == lineno)
            if position + 1 < first_member:  # a title above the first group's label
                c.info(lineno, "line", f"title line skipped: {quoted(text.strip())}")
                continue
            listed = {v for g in groups for m in g.members for v in (m.id, m.account)}
            if position + 1 == len(data) and _summary_line(text, c, listed, lineno):
                continue
            current = RawGroup(name=group_label(text), line=lineno, field="group label")
            groups.append(current)
            continue
        if current is None:
            c.error(
                lineno,
                "id (col 1)",
                f"student {quoted(fields[0])} is listed before any group label line",
            )
            continue
        if len(fields) > 2:
            c.error(
                lineno,
                "col 3",
                f"more than an id and an account on a member line: "
                f"{quoted(' '.join(fields[2:]))} not read",
            )
        member = make_member(
            c,
            fields[0],
            fields[1] if len(fields) > 1 else None,
            lineno,
            "id (col 1)",
            "account (col 2)",
            missing_account=None,
        )
        if member is not None:
            current.members.append(member)
    if skipped:
        c.info(None, "line", f"{skipped} separator line(s) between groups skipped")
    return sorted(groups, key=lambda g: natural_key(g.name))


def _is_member(fields: list[str], c: Collector) -> bool:
    return bool(fields) and (id_like(clean(fields[0], c)) or login_record(fields[0]) is not None)


def _login_member(c: Collector, group: RawGroup, login: str, lineno: int) -> None:
    """A member known by GitHub login (`Login: jjjay41223212, ID: ...`): the login is the
    account, the student id the 8 digits in it. A login without them stands in for the id
    (`RawMember.login_only`) until an alias list (`--aliases`, id -> account) gives the real
    one (`roster.corrections`); those still without one are warned about by `validate`."""
    sid = id_in_login(login)
    if sid is not None:
        member = make_member(c, sid, login, lineno, "login", "login", missing_account=None)
        if member is not None:
            member.explained = True  # the account is the one GitHub listed for the team
            group.members.append(member)
        return
    if not is_safe(login):
        c.error(lineno, "login", f"GitHub login {quoted(login)} cannot be an account")
        return
    group.members.append(
        RawMember(login, login, True, (), lineno, "login", "login", login, True, (), True)
    )


def _summary_line(text: str, c: Collector, listed: set[str], lineno: int) -> bool:
    """`All members: ['41223251', ...]` after the groups (the 2025 script printed one): a
    repeat of the members above, skipped with a note; True when it was one. A line that
    names anyone not in the groups is not skipped (it becomes an empty group: an error)."""
    if not re.search(r"[\[\]{}'\"]", text) and len(group_label(text)) <= 40:
        return False
    names = re.findall(r"[A-Za-z0-9][A-Za-z0-9_.-]*", text.partition(":")[2] or text)
    names = [n for n in names if any(ch.isdigit() for ch in n) or n in listed]
    if not names or any(n not in listed for n in names):
        return False
    c.info(lineno, "line", f"summary line skipped: its {len(names)} names are all in the groups")
    return True
