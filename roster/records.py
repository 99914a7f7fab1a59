"""Raw (pre-correction) roster records and the field cleaning every input format shares.

Parsers for TSV, CSV and YAML differ only in how they find fields; what a field
*means* -- a student id possibly followed by a hand-written mark like `*` or
`(dropped)`, an account that may be missing -- is decided here once, so the
three formats tolerate and report exactly the same things.

Raw records are mutable on purpose: corrections rewrite them in place and keep
the original text for reporting. `load.py` freezes them into `model` objects.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from .model import Diagnostic, Severity, quoted
from .repo_links import is_safe

ID_RE = re.compile(r"[A-Za-z0-9]*[0-9][A-Za-z0-9]*")
ID_MAX_LEN = 32
MARK_SYMBOLS = "*?!#†‡✓✔✗×"
_BRACKETS = {")": "(", "]": "[", "）": "（", "】": "【"}


def is_student_id(value: str) -> bool:
    """Letters and digits with at least one digit: what student ids look like everywhere we know."""
    return len(value) <= ID_MAX_LEN and ID_RE.fullmatch(value) is not None


def split_marks(raw: str) -> tuple[str, list[str]]:
    """Separate a value from annotation marks written beside it.

    `40823122*` -> ('40823122', ['*']); `40823122 (dropped)` -> ('40823122', ['(dropped)']);
    `?40823122` -> ('40823122', ['?']). Marks are teacher's notes, not part of the id.
    Callers only accept the split when what remains is a valid value, so
    `javascript:alert(1)` is reported whole rather than as `javascript:alert` + `(1)`.
    """
    s = raw.strip()
    lead: list[str] = []
    while s and s[0] in MARK_SYMBOLS:
        j = 0
        while j < len(s) and s[j] in MARK_SYMBOLS:
            j += 1
        lead.append(s[:j])
        s = s[j:].lstrip()
    trail: list[str] = []
    while s:
        last = s[-1]
        if last in MARK_SYMBOLS:
            j = len(s)
            while j > 0 and s[j - 1] in MARK_SYMBOLS:
                j -= 1
            trail.append(s[j:])
            s = s[:j].rstrip()
        elif last in _BRACKETS:
            start = s.rfind(_BRACKETS[last])
            if start < 0:
                break
            trail.append(s[start:])
            s = s[:start].rstrip()
        else:
            break
    return s, lead + trail[::-1]


def split_mark_words(raw: str, words: frozenset[str]) -> tuple[str, list[str]]:
    """Separate the teacher's mark words (`X 40823151`, `40623121 X`) from a field.

    A mark word counts only as a whole word at the start or the end of the field, so an
    account that merely contains an `X` is never touched. A field that is only a mark
    word gives ('', [word]).
    """
    tokens = raw.split()
    if not words or not tokens:
        return raw, []
    lead: list[str] = []
    while tokens and tokens[0] in words:
        lead.append(tokens.pop(0))
    trail: list[str] = []
    while tokens and tokens[-1] in words:
        trail.insert(0, tokens.pop())
    if not lead and not trail:
        return raw, []
    return " ".join(tokens), lead + trail


@dataclass(slots=True)
class RawMember:
    """A member as written, before corrections.

    `account_given` is False when the account defaulted to the id. `notes` is a
    tuple because the empty tuple is shared: 100k plain members cost no extra objects.
    """

    id: str
    account: str
    account_given: bool
    notes: tuple[str, ...]
    line: int
    field: str
    account_field: str
    raw_account: str = ""
    explained: bool = False  # an alias set or confirmed the account
    marks: tuple[str, ...] = ()
    login_only: bool = False  # known by GitHub login alone: the id stands in until an alias list


@dataclass(slots=True)
class RawGroup:
    """A group as written, before corrections."""

    name: str
    line: int
    field: str
    members: list[RawMember] = field(default_factory=list)
    leader: str | None = None
    leader_line: int = 0
    leader_field: str = ""
    leader_file: str = ""


def describe_members(members: list[RawMember]) -> str:
    """`40823101, 40823102 (account a40823102)`: every id and account, for messages about
    dropped groups."""
    parts = [
        m.id if m.account == m.id else f"{m.id} (account {quoted(m.account)})" for m in members
    ]
    return ", ".join(parts) or "none"


EXAMPLES = 5  # occurrences named in a summary of one kind of anomaly


@dataclass(slots=True)
class _Kind:
    """Every occurrence of one kind of anomaly in a file, reported together
    (`Collector.anomaly`)."""

    severity: Severity
    summary: str  # with {n} and {examples}
    found: list[tuple[int | None, str, str, str]] = field(default_factory=list)
    # (line, field, message for this one alone, short example naming it)


class Collector:
    """Gathers diagnostics for one file and aggregates the noisy, harmless ones."""

    def __init__(self, file: str, mark_words: frozenset[str] = frozenset({"X"})) -> None:
        self.file = file
        self.mark_words = mark_words  # whole words beside an id or account that are marks
        self.layout = ""  # set by the text parsers: "paired", "ids", "rows", "blocks", "lists"
        self.diagnostics: list[Diagnostic] = []
        self._trimmed = 0
        self._first_trim: tuple[int, str] | None = None
        self._kinds: dict[str, _Kind] = {}

    def anomaly(
        self,
        kind: str,
        severity: Severity,
        line: int | None,
        where: str,
        message: str,
        example: str,
        summary: str,
    ) -> None:
        """One occurrence of a kind of anomaly (an id unlike the others, an account with no
        alias...). A kind seen once is reported as ``message``; a kind seen several times is
        one diagnostic at its first line, ``summary`` with ``{n}`` (the count) and
        ``{examples}`` (the first few ``example`` texts), and each occurrence as info (shown
        with ``-v``): a file of 50 such lines gives one warning, not 50, and loses none."""
        entry = self._kinds.get(kind)
        if entry is None:
            entry = self._kinds[kind] = _Kind(severity, summary)
        entry.found.append((line, where, message, example))

    def add(self, severity: Severity, line: int | None, where: str, message: str) -> None:
        self.diagnostics.append(Diagnostic(self.file, line, where, message, severity))

    def error(self, line: int | None, where: str, message: str) -> None:
        self.add("error", line, where, message)

    def warning(self, line: int | None, where: str, message: str) -> None:
        self.add("warning", line, where, message)

    def info(self, line: int | None, where: str, message: str) -> None:
        self.add("info", line, where, message)

    def trimmed(self, line: int, where: str) -> None:
        """Count a value that had spaces around it (reported once per file, not per field)."""
        self._trimmed += 1
        if self._first_trim is None:
            self._first_trim = (line, where)

    def finish(self) -> list[Diagnostic]:
        """All diagnostics, with the aggregated ones added."""
        if self._first_trim is not None:
            line, where = self._first_trim
            self.info(
                line, where, f"spaces around {self._trimmed} value(s) trimmed (first one here)"
            )
            self._first_trim = None
        for kind in self._kinds.values():
            kind.found.sort(key=lambda found: found[0] or 0)  # examples in file order
            if len(kind.found) == 1:
                line, where, message, _ = kind.found[0]
                self.add(kind.severity, line, where, message)
                continue
            examples = ", ".join(example for *_, example in kind.found[:EXAMPLES])
            if len(kind.found) > EXAMPLES:
                examples += f" and {len(kind.found) - EXAMPLES} more (-v lists them)"
            line, where = kind.found[0][:2]
            summary = kind.summary.format(n=len(kind.found), examples=examples)
            self.add(kind.severity, line, where, summary)
            for line, where, message, _ in kind.found:
                self.info(line, where, message)
        self._kinds = {}
        return self.diagnostics


def make_member(
    c: Collector,
    id_raw: str,
    account_raw: str | None,
    line: int,
    id_field: str,
    account_field: str,
    missing_account: str | None = "no account given",
    missing_severity: Severity = "warning",
) -> RawMember | None:
    """Clean one (id, account) slot into a RawMember, reporting marks, defaults and bad ids.

    Returns None (with an error that quotes every value of the slot, so no id is
    lost silently) when the id is not an id. The caller handles fully empty slots.
    `missing_account` names the situation in the "account defaults to the id"
    warning; None suppresses it (the caller reported it once already). `missing_severity`
    is "info" where the layout expects some accounts to be missing (the course's
    one-member-a-line lists: a student who has not registered an account yet).
    """
    if id_raw != id_raw.strip():
        c.trimmed(line, id_field)
    if account_raw is not None and account_raw != account_raw.strip():
        c.trimmed(line, account_field)
    id_raw, id_words = split_mark_words(id_raw, c.mark_words)
    if account_raw is not None:
        account_raw, account_words = split_mark_words(account_raw, c.mark_words)
    else:
        account_words = []
    sid, id_marks = split_marks(id_raw)
    if sid and not is_student_id(sid):
        sid, id_marks = id_raw.strip(), []  # not "id + mark": report the raw text as it is
    account, account_marks = split_marks(account_raw or "")
    if account and not is_safe(account):
        account, account_marks = (account_raw or "").strip(), []
    if not sid:
        if account or account_marks:
            c.error(
                line,
                id_field,
                f"student id is empty but the account {quoted(account_raw or '')} is given"
                + (f" (with {quoted(id_raw.strip())})" if id_raw.strip() else ""),
            )
        elif id_words or account_words:
            c.warning(
                line,
                id_field,
                f"slot holds only the mark(s) {quoted(' '.join(id_words + account_words))} "
                "and no student id",
            )
        elif id_marks:
            # Digits in a lone annotation may be a student id written oddly: never drop it quietly.
            report = c.error if any(ch.isdigit() for ch in id_raw) else c.warning
            report(
                line,
                id_field,
                f"slot holds only the annotation {quoted(id_raw.strip())} and no student id",
            )
        return None
    if not is_student_id(sid):
        extra = (
            f"; its account {quoted(account_raw)} is not used"
            if account_raw and account_raw.strip()
            else ""
        )
        c.error(
            line,
            id_field,
            f"{quoted(id_raw.strip())} is not a student id "
            f"(letters and digits, at least one digit){extra}",
        )
        return None
    notes = tuple(id_marks + account_marks)
    bad = next(
        (n for n in notes if any(ord(ch) < 0x20 or 0x7F <= ord(ch) < 0xA0 for ch in n)), None
    )
    if bad is not None:  # would reach a terminal or a page raw: refuse, as for any value
        c.error(line, id_field, f"annotation {quoted(bad)} beside {sid} holds a control character")
        return None
    for words, where in ((id_words, id_field), (account_words, account_field)):
        for word in words:
            c.info(line, where, f"mark {quoted(word)} beside {sid} kept on the member")
    for marks, where in ((id_marks, id_field), (account_marks, account_field)):
        for mark in marks:
            c.anomaly(
                "annotation",
                "warning",
                line,
                where,
                f"annotation {quoted(mark)} beside {sid} kept as a member note",
                f"{quoted(mark)} beside {sid} (line {line})",
                "{n} annotations beside ids kept as member notes: {examples}",
            )
    given = bool(account)
    if not given:
        if missing_account is not None and not account_words:  # `40823151<TAB>X`: a mark
            c.anomaly(
                f"no account: {missing_account}",
                missing_severity,
                line,
                account_field,
                f"{missing_account} for {sid}; the account defaults to the id",
                f"{sid} (line {line})",
                f"{missing_account} for {{n}} members; each account defaults to the id: "
                "{examples}",
            )
        account = sid
    return RawMember(
        id=sid,
        account=account,
        account_given=given,
        notes=notes,
        line=line,
        field=id_field,
        account_field=account_field,
        raw_account=(account_raw or "").strip(),
        marks=tuple(id_words + account_words),
    )
