"""Checks on the corrected roster: what would publish wrong links or wrong groups.

Errors are things that make the published roster wrong or unsafe (a student in
two groups, duplicate group names, unsafe URL parts). Warnings are things that
are probably typos but can be legitimate (an id unlike the others: a student
repeating the course from an earlier year; an account GitHub would not accept
today), so they are shown but do not block the site.
"""

from __future__ import annotations

import re
import unicodedata
from collections import Counter

from .model import quoted
from .records import Collector, RawGroup, RawMember, is_student_id
from .repo_links import github_username_problem, unsafe_reason

NAME_EXTRA_CHARS = " _-.+()"


def slug_for(name: str) -> str:
    """A group's URL slug: its name with runs of whitespace turned into `-` (as GitHub does
    for repository names)."""
    return re.sub(r"\s+", "-", name.strip())


def _name_problem(name: str) -> str | None:
    """Why a group name is not acceptable, or None."""
    if len(name) > 100:
        return "is longer than 100 characters"
    for ch in name:
        if not (ch.isalnum() or ch in NAME_EXTRA_CHARS) or unicodedata.category(ch).startswith("C"):
            return (
                f"contains the forbidden character {quoted(ch)} "
                "(allowed: letters, digits, space, _ - . + ( ))"
            )
    return None


def _majority(values: list[str]) -> str | None:
    """The value more than half of `values` share, if any."""
    if len(values) < 3:
        return None
    value, count = Counter(values).most_common(1)[0]
    return value if count * 2 > len(values) else None


def validate(
    groups: list[RawGroup],
    c: Collector,
    course_repo: str,
    expected_ids: set[str] | frozenset[str] = frozenset(),
) -> None:
    """Report every validation error and warning on corrected raw groups into `c`."""
    reason = unsafe_reason(course_repo)
    if reason:
        c.error(
            0,
            "course_repo",
            f"course repo {quoted(course_repo)} {reason}; no member links can be made",
        )
    _check_groups(groups, c)
    members = [m for g in groups for m in g.members]
    _check_memberships(groups, c)
    _check_id_shapes([m for m in members if m.id not in expected_ids and not m.login_only], c)
    _check_near_duplicates([m for m in members if not m.login_only], c, expected_ids)
    _check_accounts(members, c)
    for m in members:
        if m.login_only:
            c.anomaly(
                "login without id",
                "warning",
                m.line,
                m.field,
                f"GitHub login {quoted(m.account)} holds no student id; "
                "the login stands in for the id",
                f"{m.account} (line {m.line})",
                "{n} members are known by GitHub login alone (no student id in it); each "
                "login stands in for the id until an alias list (--aliases, id -> account) "
                "names them: {examples}",
            )


def _check_groups(groups: list[RawGroup], c: Collector) -> None:
    names: dict[str, RawGroup] = {}
    slugs: dict[str, RawGroup] = {}
    for g in groups:
        problem = _name_problem(g.name)
        if problem:
            c.error(g.line, g.field, f"group name {quoted(g.name)} {problem}")
        if g.name in names:
            c.error(
                g.line,
                g.field,
                f"two groups named {quoted(g.name)} (the other is on line {names[g.name].line})",
            )
        names.setdefault(g.name, g)
        slug = slug_for(g.name)
        reason = unsafe_reason(slug)
        if reason and not problem:
            c.error(
                g.line,
                g.field,
                f"group slug {quoted(slug)} {reason}; "
                "rename the group with a group_names rule in the corrections file",
            )
        other = slugs.get(slug.lower())
        if other is not None and other.name != g.name:
            c.error(
                g.line,
                g.field,
                f"groups {quoted(other.name)} (line {other.line}) and {quoted(g.name)} "
                f"have the same slug {quoted(slug)}",
            )
        slugs.setdefault(slug.lower(), g)
        if not g.members:
            c.error(g.line, g.field, f"group {quoted(g.name)} has no members")
        if g.leader is not None and g.leader not in {m.id for m in g.members}:
            where = c.file if g.leader_file == c.file else g.leader_file
            c.add(
                "error",
                g.leader_line or g.line,
                g.leader_field or g.field,
                f"leader {quoted(g.leader)} is not a member of group {quoted(g.name)}"
                + ("" if where == c.file else f" (set in {where})"),
            )


def _check_memberships(groups: list[RawGroup], c: Collector) -> None:
    first: dict[str, tuple[RawGroup, RawMember]] = {}
    for g in groups:
        for m in g.members:
            if not is_student_id(m.id) and not m.login_only:
                c.error(m.line, m.field, f"{quoted(m.id)} is not a student id (after corrections)")
            seen = first.get(m.id)
            if seen is None:
                first[m.id] = (g, m)
            elif seen[0] is g:
                c.error(
                    m.line,
                    m.field,
                    f"student {m.id} is listed twice in group {quoted(g.name)} "
                    f"(also line {seen[1].line}, {seen[1].field})",
                )
            elif m.marks or seen[1].marks:
                marked = m if m.marks else seen[1]
                c.warning(
                    m.line,
                    m.field,
                    f"student {m.id} is in two groups: {quoted(seen[0].name)} "
                    f"(line {seen[1].line}) and {quoted(g.name)}; "
                    f"marked {' '.join(marked.marks)} on line {marked.line}",
                )
            else:
                c.error(
                    m.line,
                    m.field,
                    f"student {m.id} is in two groups: {quoted(seen[0].name)} "
                    f"(line {seen[1].line}) and {quoted(g.name)}",
                )


def _check_id_shapes(members: list[RawMember], c: Collector) -> None:
    """Warn about ids whose length or 3-character prefix differs from most ids in the file
    (students from earlier cohorts, or typos): one warning for all of them."""
    length = _majority([str(len(m.id)) for m in members])
    prefix = _majority([m.id[:3] for m in members])
    most = " and ".join(
        part
        for part in (
            f"{length} characters" if length else "",
            f"start with {prefix!r}" if prefix else "",
        )
        if part
    )
    for m in members:
        why = []
        if length is not None and str(len(m.id)) != length:
            why.append(f"{len(m.id)} characters where most ids have {length}")
        if prefix is not None and m.id[:3] != prefix:
            why.append(f"starts with {m.id[:3]!r} where most ids start with {prefix!r}")
        if why:
            c.anomaly(
                "id shape",
                "warning",
                m.line,
                m.field,
                f"id {m.id} looks unlike the others: {'; '.join(why)}",
                f"{m.id} (line {m.line})",
                f"{{n}} ids look unlike the others (most ids are {most}): {{examples}}; "
                "students from other cohorts? (list them under expected_ids in the "
                "corrections to silence this)",
            )


_PREFIX = re.compile(r"[A-Za-z]*[-_.]?")
_SUFFIX = re.compile(r"(?:[-_.][A-Za-z0-9]+|[A-Za-z][A-Za-z0-9]*)?")


def id_with_letters(account: str, sid: str) -> bool:
    """Whether ``account`` is the student id with letters before or a suffix after it
    (`s40723140`, `a40823112`, `40923126-1`, `40923149r`): the usual GitHub account when the
    bare id was taken, never a column slip. A digit glued on (`409231044`) is not."""
    start = account.lower().find(sid.lower())
    if start < 0 or account.lower() == sid.lower():
        return False
    return bool(
        _PREFIX.fullmatch(account[:start]) and _SUFFIX.fullmatch(account[start + len(sid) :])
    )


def _check_accounts(members: list[RawMember], c: Collector) -> None:
    ids = {m.id for m in members}
    owners: dict[str, RawMember] = {}
    for m in members:
        reason = unsafe_reason(m.account)
        if reason:
            shown = m.raw_account if m.raw_account and m.raw_account != m.account else m.account
            c.error(
                m.line,
                m.account_field,
                f"account {quoted(shown)} {reason}; no link is made for {m.id}",
            )
            continue
        example = f"{m.account} for {m.id} (line {m.line})"
        problem = github_username_problem(m.account)
        if problem:
            c.anomaly(
                "github username",
                "warning",
                m.line,
                m.account_field,
                f"account {quoted(m.account)} {problem}",
                example,
                "{n} accounts are not valid GitHub usernames: {examples}",
            )
        if m.account != m.id and not m.explained:
            _account_differs(m, ids, example, c)
        other = owners.get(m.account.lower())
        if other is not None and other.id != m.id:
            c.anomaly(
                "shared account",
                "warning",
                m.line,
                m.account_field,
                f"account {quoted(m.account)} is also used by {other.id} (line {other.line}); "
                "their links will be the same",
                f"{m.account} for {other.id} and {m.id} (lines {other.line}, {m.line})",
                "{n} accounts are used by two students (their links will be the same): {examples}",
            )
        owners.setdefault(m.account.lower(), m)


def _account_differs(m: RawMember, ids: set[str], example: str, c: Collector) -> None:
    """An account unlike its id with no alias: the id with letters added is the usual GitHub
    form (info); an account that is itself an id hints at a column slip; anything else asks
    for an alias. Each kind is one line however many members it concerns."""
    shown = quoted(m.account)
    if id_with_letters(m.account, m.id):
        c.anomaly(
            "account is id with letters",
            "info",
            m.line,
            m.account_field,
            f"account {shown} is the id {m.id} with letters added",
            example,
            "{n} accounts are the student id with letters added (the usual form when the "
            "bare id was taken on GitHub): {examples}",
        )
    elif m.account in ids or m.account.isdigit():
        c.anomaly(
            "account looks like an id",
            "warning",
            m.line,
            m.account_field,
            f"account {shown} differs from id {m.id} with no alias; "
            "it looks like another student id; is a column missing?",
            example,
            "{n} accounts look like student ids but not the member's own (a typo, or a "
            "column missing?): {examples}",
        )
    else:
        c.anomaly(
            "account differs",
            "warning",
            m.line,
            m.account_field,
            f"account {shown} differs from id {m.id} with no alias; "
            "add an alias to the corrections file if it is right",
            example,
            "{n} accounts differ from the student id with no alias: {examples}; add aliases "
            "(corrections file or an alias list) if they are right",
        )


SERIAL_DIGITS = 3  # the last digits of an id number students within a class


def _one_edit_variants(value: str) -> list[tuple[str, str]]:
    """(variant, how) for every adjacent transposition and every one-digit change."""
    out = []
    for i in range(len(value) - 1):
        if value[i] != value[i + 1]:
            swapped = value[:i] + value[i + 1] + value[i] + value[i + 2 :]
            out.append((swapped, "one transposition"))
    for i, ch in enumerate(value):
        if ch.isdigit():
            for d in "0123456789":
                if d != ch:
                    out.append((value[:i] + d + value[i + 1 :], "one digit"))
    return out


def _check_near_duplicates(
    members: list[RawMember], c: Collector, expected_ids: set[str] | frozenset[str]
) -> None:
    """Warn about an id that is one typo away from another id, or from the class's id range.

    Ids of one class share a prefix (year, department) and differ in the last
    SERIAL_DIGITS digits, so two ids one digit apart *there* are simply two students. A
    slip in the prefix is what a typo looks like: `40832244` beside `40823244`. So only
    pairs whose prefixes differ are reported, and an id outside the class's prefix that
    one edit would put inside the range the class uses (first to last id of the
    majority prefix). `expected_ids` in the corrections silences an id.
    """
    ids: dict[str, RawMember] = {}
    for m in members:
        ids.setdefault(m.id, m)
    if len(ids) < 2:
        return

    def prefix(value: str) -> str:
        return value[:-SERIAL_DIGITS] if len(value) > SERIAL_DIGITS else ""

    common = _majority([prefix(v) for v in ids if prefix(v)])
    class_ids = sorted(v for v in ids if common and prefix(v) == common)
    low, high = (class_ids[0], class_ids[-1]) if class_ids else ("", "")
    reported: set[frozenset[str]] = set()
    for sid, m in ids.items():
        if sid in expected_ids or prefix(sid) == common or not prefix(sid):
            continue
        near_range = None
        for variant, how in _one_edit_variants(sid):
            other = ids.get(variant)
            if other is not None and variant not in expected_ids:
                if prefix(variant) == prefix(sid) or frozenset((sid, variant)) in reported:
                    continue
                reported.add(frozenset((sid, variant)))
                _near(
                    c,
                    m,
                    f"id {sid} is {how} away from {variant} (line {other.line}, {other.field}); "
                    "a typo? (add it to expected_ids in the corrections if both are right)",
                    f"{sid} ~ {variant} (lines {m.line}, {other.line})",
                )
                near_range = None
                break
            if (
                near_range is None
                and common
                and prefix(variant) == common
                and len(variant) == len(low)
                and low <= variant <= high
            ):
                near_range = (variant, how)
        if near_range is not None:
            variant, how = near_range
            _near(
                c,
                m,
                f"id {sid} is outside the class's id range {low}-{high} "
                f"but {how} away from {variant} "
                "inside it; a typo? (add it to expected_ids in the corrections if it is right)",
                f"{sid} ~ {variant} (line {m.line}, outside {low}-{high})",
            )


def _near(c: Collector, m: RawMember, message: str, example: str) -> None:
    c.anomaly(
        "near duplicate",
        "warning",
        m.line,
        m.field,
        message,
        example,
        "{n} ids are one typo away from another id or from the class's id range: "
        "{examples}; typos? (add them to expected_ids in the corrections if they are right)",
    )
