"""The roster data model: what every parser produces and every emitter consumes.

The final objects (`Member`, `Group`, `Roster`) are frozen so that a loaded roster
can be shared by the site pipeline and the CLI without anyone mutating it behind
the other's back. Problems found while loading are *data* (`Diagnostic`), not
exceptions, so one run can report every problem in a file at once; only a file
that cannot be read at all raises `RosterError`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

from .links import group_urls, member_urls

Severity = Literal["error", "warning", "info"]

_CONTROL_ESCAPES = {"\t": "\\t", "\n": "\\n", "\r": "\\r"}


def printable(text: str) -> str:
    """Escape control and line-separator characters so a message stays on one line.

    Diagnostics quote raw input; a stray tab, CR or NUL in a field must not break
    the one-line `file:line: field: message` format or a terminal.
    """
    out = []
    for ch in text:
        code = ord(ch)
        if ch in _CONTROL_ESCAPES:
            out.append(_CONTROL_ESCAPES[ch])
        elif code < 0x20 or 0x7F <= code < 0xA0 or ch in "\u2028\u2029\u200b\u200e\u200f\ufeff":
            out.append(f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}")
        else:
            out.append(ch)
    return "".join(out)


def quoted(value: str) -> str:
    """Quote a raw input value for a message (single quotes, control chars escaped)."""
    return "'" + printable(value) + "'"


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """One finding about an input file, located precisely enough to fix it.

    `line` is 1-based; 0 means "the file as a whole". `field` is a column
    (`col 4`), a member slot (`member 3 id (col 6)`) or a key path
    (`typos.4823122`) -- whatever lets a person find the spot.
    """

    severity: Severity
    file: str
    line: int
    field: str
    message: str

    def __str__(self) -> str:
        return f"{printable(self.file)}:{self.line}: {printable(self.field)}: {printable(self.message)}"


class RosterError(Exception):
    """The roster (or corrections) file could not be read at all.

    Malformed *content* never raises; it becomes error diagnostics. This is only
    for missing/unreadable files and unsupported file types.
    """

    def __init__(self, file: str, line: int, field: str, message: str) -> None:
        self.file = file
        self.line = line
        self.field = field
        self.message = message
        super().__init__(str(self))

    def __str__(self) -> str:
        return str(Diagnostic("error", self.file, self.line, self.field, self.message))


@dataclass(frozen=True, slots=True)
class Member:
    """A student: id, GitHub account, annotation notes, and where they were written."""

    id: str
    account: str
    notes: tuple[str, ...] = ()
    line: int = 0
    field: str = ""


@dataclass(frozen=True, slots=True)
class Group:
    """A project group. `slug` is what goes into URLs; `leader` is a member's id."""

    name: str
    slug: str
    leader: str
    members: tuple[Member, ...]
    line: int = 0

    @property
    def leader_member(self) -> Member | None:
        """The member whose account owns the group repo and site (None if not a member)."""
        for member in self.members:
            if member.id == self.leader:
                return member
        return None


@dataclass(frozen=True, slots=True)
class Roster:
    """All groups in input order."""

    groups: tuple[Group, ...]

    @property
    def members(self) -> list[Member]:
        """Every member of every group, in input order."""
        return [m for g in self.groups for m in g.members]


@dataclass
class RosterResult:
    """What `load_roster` returns: the roster plus everything noticed on the way."""

    roster: Roster
    diagnostics: list[Diagnostic] = field(default_factory=list)
    corrections_applied: list[Diagnostic] = field(default_factory=list)
    file: str = ""
    corrections_file: str | None = None
    course_repo: str = "cd2021"
    format: str = ""

    @property
    def errors(self) -> list[Diagnostic]:
        """Error diagnostics: the roster must not be published while any exist."""
        return [d for d in self.diagnostics if d.severity == "error"]

    @property
    def warnings(self) -> list[Diagnostic]:
        """Warnings: suspicious but tolerated input."""
        return [d for d in self.diagnostics if d.severity == "warning"]

    @property
    def infos(self) -> list[Diagnostic]:
        """Informational notes (blank lines skipped, CRLF normalised, ...)."""
        return [d for d in self.diagnostics if d.severity == "info"]

    @property
    def ok(self) -> bool:
        """True when there are no errors."""
        return not self.errors

    def to_dict(self) -> dict[str, Any]:
        """The roster with its links, as plain data (JSON-ready, input order kept).

        A URL is None where the account or slug was unsafe (an error was reported).
        """
        groups = []
        for group in self.roster.groups:
            repo_url, site_url = group_urls(group)
            members = []
            for member in group.members:
                m_repo, m_site = member_urls(member, self.course_repo)
                members.append(
                    {
                        "id": member.id,
                        "account": member.account,
                        "repo_url": m_repo,
                        "site_url": m_site,
                        "notes": list(member.notes),
                    }
                )
            groups.append(
                {
                    "name": group.name,
                    "slug": group.slug,
                    "leader": group.leader,
                    "repo_url": repo_url,
                    "site_url": site_url,
                    "members": members,
                }
            )
        return {"groups": groups}
