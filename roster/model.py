"""The roster data model: what every parser produces and every emitter consumes.

The final objects (`Member`, `Group`, `Roster`) are frozen so that a loaded roster
can be shared by the site pipeline and the CLI without anyone mutating it behind
the other's back. Problems found while loading are *data* (`Diagnostic`), not
exceptions, so one run can report every problem in a file at once; only a file
that cannot be read at all raises `RosterError`. Both are the shared located form
(`located.diagnostics`), re-exported here.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from located.diagnostics import WHOLE_FILE, Diagnostic, LocatedError, Severity, printable, quoted

from .repo_links import repo_url, site_url

__all__ = [
    "WHOLE_FILE",
    "Diagnostic",
    "Group",
    "MarkRule",
    "Member",
    "Roster",
    "RosterError",
    "RosterResult",
    "Severity",
    "printable",
    "quoted",
]


class RosterError(LocatedError):
    """The roster (or corrections) file could not be read at all.

    Malformed *content* never raises; it becomes error diagnostics. This is only
    for missing/unreadable files and unsupported file types. ``line`` is None
    (:data:`WHOLE_FILE`) when the problem is the file as a whole.
    """

    def __init__(self, file: str, line: int | None, field: str, message: str) -> None:
        super().__init__(Diagnostic(file, line, field, message))


@dataclass(frozen=True, slots=True)
class Member:
    """A student: id, GitHub account, annotation notes, and where they were written.

    `marks` are the teacher's mark words written beside the id or account (`X 40823151`,
    `40623121 X`): data, kept in order, whose meaning the corrections file gives (`MarkRule`).
    """

    id: str
    account: str
    notes: tuple[str, ...] = ()
    line: int = 0
    field: str = ""
    marks: tuple[str, ...] = ()

    def urls(self, course_repo: str) -> tuple[str | None, str | None]:
        """The member's personal course repo and site (None where a part is unsafe)."""
        return repo_url(self.account, course_repo), site_url(self.account, course_repo)


@dataclass(frozen=True, slots=True)
class MarkRule:
    """What a mark word means: a sentence for readers, whether the member is linked, struck."""

    word: str
    meaning: str = ""
    links: bool = True
    strike: bool = False


DEFAULT_MARKS = (MarkRule("X"),)


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

    def urls(self) -> tuple[str | None, str | None]:
        """The group's repo and site, both owned by the leader's account."""
        leader = self.leader_member
        if leader is None:
            return None, None
        return repo_url(leader.account, self.slug), site_url(leader.account, self.slug)


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
    aliases_file: str | None = None
    course_repo: str = "cd2021"
    format: str = ""
    layout: str = ""  # text rosters: the layout read (roster.detect.TEXT_LAYOUTS)
    mark_rules: dict[str, MarkRule] = field(default_factory=dict)

    def marks_of(self, member: Member) -> list[MarkRule]:
        """The rules of a member's marks (a mark without a rule means only "marked")."""
        return [self.mark_rules.get(m) or MarkRule(m) for m in member.marks]

    def linked(self, member: Member) -> bool:
        """False when one of the member's marks says the member is left out of links."""
        return all(rule.links for rule in self.marks_of(member))

    def member_links(self, member: Member) -> tuple[str | None, str | None]:
        """The member's repo and site URLs; (None, None) when unsafe or marked as not linked."""
        if not self.linked(member):
            return None, None
        return member.urls(self.course_repo)

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
            group_repo, group_site = group.urls()
            members = []
            for member in group.members:
                m_repo, m_site = self.member_links(member)
                entry: dict[str, Any] = {
                    "id": member.id,
                    "account": member.account,
                    "repo_url": m_repo,
                    "site_url": m_site,
                    "notes": list(member.notes),
                }
                if member.marks:
                    entry["marks"] = list(member.marks)
                members.append(entry)
            groups.append(
                {
                    "name": group.name,
                    "slug": group.slug,
                    "leader": group.leader,
                    "repo_url": group_repo,
                    "site_url": group_site,
                    "members": members,
                }
            )
        return {"groups": groups}
