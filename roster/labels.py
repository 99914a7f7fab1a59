"""The words a roster uses for its columns and group labels, and what an id looks like.

Headers in the course's files change every year (`組別`, `2a / github 帳號 / 組別`, `學號`,
`member 1`, `GitHub帳號`, a spreadsheet export's `學號,姓名,組別`), so columns are recognised
by vocabulary here, once, for the tab-separated layouts, the CSV reader and alias lists alike.
"""

from __future__ import annotations

import re

from .records import is_student_id

#: A column label (whole cell, case-insensitive, spaces ignored) -> the column's role.
_ROLES: list[tuple[str, re.Pattern[str]]] = [
    (
        "account",
        re.compile(
            r"(github)?(帳號|帐号|账号|account|accounts|login|username|user|使用者名稱)"
            r"|github(帳號|帐号|账号|account|id|user|username)?",
            re.I,
        ),
    ),
    (
        "group",
        re.compile(
            r"組別|组别|組名|组名|組號|分組|分组|組|组|小組|组序|組序"
            r"|group|groups|grp|team",
            re.I,
        ),
    ),
    (
        "id",
        re.compile(
            r"學號|学号|學生|学生|studentid|studentno|student|studno|stud_no|stdno|id|no\.?|number",
            re.I,
        ),
    ),
    ("name", re.compile(r"姓名|名字|name|fullname|studentname", re.I)),
    ("notes", re.compile(r"備註|备注|註記|notes?|remarks?|comments?", re.I)),
]
#: Labels of the member columns of one-group-a-line layouts (`組員1`, `member 2`, `學號3`).
MEMBER_LABEL = re.compile(
    r"(組員|成員|學號|帳號|member|student|id|account|github)[\s_-]*\d*", re.IGNORECASE
)
#: Headers of the first column of one-group-a-line layouts.
GROUP_HEADERS = {"組別", "組名", "分組", "組", "小組", "group", "groups", "team", "name"}
ACCOUNT_LABEL = re.compile(r"帳號|account|github", re.IGNORECASE)

_SEPARATOR = re.compile(r"[-=_*~#.·—–+|]{3,}")


def column_role(label: str) -> str | None:
    """`github 帳號` -> "account", `組別` -> "group", `學號` -> "id", `姓名` -> "name"."""
    key = re.sub(r"[\s:：_-]+", "", label).strip()
    if not key:
        return None
    for role, pattern in _ROLES:
        if pattern.fullmatch(key):
            return role
    return None


def id_like(value: str) -> bool:
    """Looks like a student id rather than a group number or a name: letters and digits, at
    least five digits, and more digits than letters (`40923101`, `s40723140`; not `2ag1`,
    `1`, `jason60714`). Used to tell the layouts apart; an id field itself is checked by
    `records.is_student_id`."""
    if not is_student_id(value):
        return False
    digits = sum(ch.isdigit() for ch in value)
    return digits >= 5 and digits * 2 > len(value)


def is_separator(line: str) -> bool:
    """`--------------------` between groups (the 2019 lists), `=====`: not data."""
    return _SEPARATOR.fullmatch(line.strip()) is not None


def natural_key(text: str) -> tuple:
    """Sort key putting `group 2` before `group 10` and `2ag2` before `2ag10`."""
    return tuple(
        (0, int(part), "") if part.isdigit() else (1, 0, part.lower())
        for part in re.split(r"(\d+)", text)
        if part
    )


def group_label(text: str) -> str:
    """A label line as a group name: `group 1:` -> `group 1`, `第一組：` -> `第一組`,
    `Processing team: g1` (GitHub's team list) -> `g1`."""
    name = re.sub(r"\s+", " ", text.strip().rstrip(":：").strip())
    before, colon, after = name.rpartition(":")
    return after.strip() if colon and after.strip() else name


_LOGIN = re.compile(r"^\s*login\s*[:：]\s*([^\s,]+)", re.IGNORECASE)
_ID_IN_LOGIN = re.compile(r"(?<![0-9])[0-9]{8}(?![0-9])")


def login_record(line: str) -> str | None:
    """The GitHub login of a `Login: 41223251, ID: 144990130, URL: ...` line (the members of
    a GitHub team as the course's 2025 script printed them), else None."""
    m = _LOGIN.match(line)
    return m.group(1) if m else None


def id_in_login(login: str) -> str | None:
    """The student id inside a login: `41223251`, `jjjay41223212`, `41223208-hw` -> 8 digits;
    None when there is no single 8-digit run (`leeshaowei0716`)."""
    found = _ID_IN_LOGIN.findall(login)
    return found[0] if len(found) == 1 else None
