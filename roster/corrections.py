"""Corrections as data: a YAML file of fixes applied to a roster, each one reported.

The course script fixed its roster with hard-coded `replace()` calls on whole
lines, which also hit substrings and left no record. Here each fix is a named,
line-numbered entry; every place it changes something is reported
(`corrections_applied`), and an entry that matched nothing is a warning -- it
is either stale (the roster was fixed) or mistyped itself.

    typos:        {wrong: right}          exact id or account values
    aliases:      {student id: account}   the GitHub account of a student
    group_names:  [{replace: "_", with: "-"}, {regex: "^x", with: "y"}]
    leaders:      {final group name: student id}
    expected_ids: {student id: reason}   ids that rightly look unlike the others
    marks:        {word: meaning} or {word: {meaning: ..., links: false, strike: true}}

Group-name regexes run on the `regex` engine with a time limit (REGEX_TIMEOUT seconds per
substitution): Python's `re` cannot be interrupted, and a pattern such as `(x+x+)+y`
backtracks for hours on a 30-character name. A rule that runs out of time is an error
naming the rule's line; the build goes on without it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import regex
import yaml

from .aliases import Alias
from .model import Diagnostic, MarkRule, quoted
from .records import Collector, RawGroup, RawMember
from .source import decode, read_bytes
from .yamlnodes import ROOT, Node, Walker, compose, line_of

KEYS = ("typos", "aliases", "group_names", "leaders", "expected_ids", "marks")
MARK_KEYS = ("meaning", "links", "strike")
REGEX_TIMEOUT = 1.0  # seconds one group-name substitution may take
_BOOLS = {"true": True, "yes": True, "on": True, "false": False, "no": False, "off": False}


@dataclass
class Entry:
    """One `key: value` correction and where it was written."""

    key: str
    value: str
    line: int
    field: str
    matched: bool = False


@dataclass
class NameRule:
    """A group-name rule: literal `replace` or `regex`, applied in file order."""

    kind: str
    pattern: str
    replacement: str
    line: int
    field: str
    regex: regex.Pattern[str] | None = None
    matched: bool = False


@dataclass
class Corrections:
    """A parsed corrections file."""

    file: str
    typos: dict[str, Entry] = field(default_factory=dict)
    aliases: dict[str, Entry] = field(default_factory=dict)
    group_names: list[NameRule] = field(default_factory=list)
    leaders: dict[str, Entry] = field(default_factory=dict)
    # ids that rightly look unlike the others (e.g. a student repeating the course from an
    # earlier cohort): id -> reason. Silences the id-shape warning for exactly those ids.
    expected_ids: dict[str, Entry] = field(default_factory=dict)
    marks: dict[str, MarkRule] = field(default_factory=dict)  # mark word -> what it means
    # an alias list given beside the corrections (`aliases=`, roster.aliases): id -> account
    listed_aliases: dict[str, Alias] = field(default_factory=dict)

    def entries(self) -> list[Entry | NameRule]:
        return [
            *self.typos.values(),
            *self.aliases.values(),
            *self.group_names,
            *self.leaders.values(),
            *self.expected_ids.values(),
        ]


def load_corrections(path: Path) -> tuple[Corrections, list[Diagnostic]]:
    """Read and check a corrections file. Raises RosterError only if it cannot be read."""
    file = str(path)
    c = Collector(file)
    source = decode(read_bytes(path), file, "yaml")
    c.diagnostics.extend(source.diagnostics)
    corr = Corrections(file)
    root = compose(source.text, c)
    if root is None:
        return corr, c.finish()
    w = Walker(c)
    for key, key_node, value in w.mapping(root, ROOT):
        if key in ("typos", "aliases", "leaders", "expected_ids"):
            table: dict[str, Entry] = getattr(corr, key)
            for k, k_node, v_node in w.mapping(value, key):
                v = w.text(v_node, f"{key}.{k}")
                if not k.strip() or v is None:
                    if not k.strip():
                        c.error(line_of(k_node), key, "empty key")
                    continue
                table[k.strip()] = Entry(k.strip(), v, line_of(k_node), f"{key}.{k.strip()}")
                if key == "typos" and k.strip() == v:
                    c.warning(
                        line_of(k_node),
                        f"{key}.{k}",
                        "typo maps a value to itself; it does nothing",
                    )
        elif key == "marks":
            for word, word_node, v_node in w.mapping(value, key):
                rule = _mark_rule(w, word.strip(), line_of(word_node), v_node)
                if rule is not None:
                    corr.marks[rule.word] = rule
        elif key == "group_names":
            for i, item in enumerate(w.sequence(value, key), 1):
                rule = _name_rule(w, item, f"group_names[{i}]")
                if rule is not None:
                    corr.group_names.append(rule)
        else:
            c.error(
                line_of(key_node), key, f"unknown key {key!r} (expected one of: {', '.join(KEYS)})"
            )
    return corr, c.finish()


def _mark_rule(w: Walker, word: str, line: int, node: Node) -> MarkRule | None:
    """One `marks:` entry: a scalar meaning, or {meaning, links, strike}."""
    c = w.c
    where = f"marks.{word}"
    if not word or any(ch.isspace() for ch in word):
        c.error(line, where, "a mark must be one word (it is matched as a whole word)")
        return None
    if any(ch.isdigit() for ch in word):
        c.error(line, where, "a mark must not contain digits (it could be read as an id)")
        return None
    if isinstance(node, yaml.ScalarNode):
        meaning = w.text(node, where, allow_empty=True)
        return MarkRule(word, meaning or "")
    found: dict[str, object] = {}
    for key, key_node, value in w.mapping(node, where):
        if key not in MARK_KEYS:
            c.error(
                line_of(key_node),
                f"{where}.{key}",
                f"unknown key {key!r} (expected one of: {', '.join(MARK_KEYS)})",
            )
            continue
        text = w.text(value, f"{where}.{key}", allow_empty=(key == "meaning"))
        if text is None:
            continue
        if key == "meaning":
            found[key] = text
        elif text.lower() in _BOOLS:
            found[key] = _BOOLS[text.lower()]
        else:
            c.error(line_of(value), f"{where}.{key}", f"must be true or false, got {quoted(text)}")
    return MarkRule(
        word,
        str(found.get("meaning", "")),
        bool(found.get("links", True)),
        bool(found.get("strike", False)),
    )


def _name_rule(w: Walker, node: Node, where: str) -> NameRule | None:
    """Check one `{replace|regex: ..., with: ...}` item."""
    c = w.c
    found: dict[str, str] = {}
    line = line_of(node)
    for key, key_node, value in w.mapping(node, where):
        if key not in ("replace", "regex", "with"):
            c.error(
                line_of(key_node),
                f"{where}.{key}",
                f"unknown key {key!r} (expected replace or regex, and with)",
            )
            continue
        text = w.text(value, f"{where}.{key}", allow_empty=(key == "with"))
        if text is not None:
            found[key] = value.value if key == "with" else text  # keep spaces in replacements
    kinds = [k for k in ("replace", "regex") if k in found]
    if len(kinds) != 1 or "with" not in found:
        c.error(
            line, where, "a group_names rule needs exactly one of 'replace' or 'regex', and 'with'"
        )
        return None
    kind = kinds[0]
    rule = NameRule(kind, found[kind], found["with"], line, where)
    if kind == "regex":
        try:
            rule.regex = regex.compile(found[kind], flags=regex.V0)
        except regex.error as exc:
            c.error(line, f"{where}.regex", f"invalid regular expression: {exc}")
            return None
    return rule


def apply_corrections(
    groups: list[RawGroup], corr: Corrections, roster_file: str
) -> tuple[list[Diagnostic], list[Diagnostic]]:
    """Apply corrections in place. Returns (corrections applied, problems found).

    The steps run in a fixed order because each one sees the previous one's result: typos
    first (an alias or leader is written with the corrected id), then aliases, group-name
    rules (leaders are keyed by the final group name), leaders, expected ids, and last the
    entries that matched nothing."""
    run = _Run(corr, roster_file)
    for step in (_fix_typos, _apply_aliases, _rename_groups, _set_leaders, _note_expected_ids):
        step(run, groups)
    _warn_unmatched(run)
    return run.applied, run.problems.finish()


@dataclass
class _Run:
    """One application of a corrections file: what was applied, what went wrong."""

    corr: Corrections
    roster_file: str
    applied: list[Diagnostic] = field(default_factory=list)
    problems: Collector = field(init=False)

    def __post_init__(self) -> None:
        self.problems = Collector(self.corr.file)

    def report(self, line: int, where: str, message: str, entry: Entry | NameRule) -> None:
        """Record a change at the roster's spot, naming the correction's line; mark it used."""
        entry.matched = True
        note = f"{message} [{self.corr.file}:{entry.line}]"
        self.applied.append(Diagnostic(self.roster_file, line, where, note, "info"))


def _fix_typos(run: _Run, groups: list[RawGroup]) -> None:
    """Exact-value typos in ids, written accounts and written leaders."""
    typos = run.corr.typos
    for group in groups:
        for m in group.members:
            typo = typos.get(m.id)
            if typo is not None:
                run.report(
                    m.line, m.field, f"typo: id {quoted(m.id)} -> {quoted(typo.value)}", typo
                )
                m.id = typo.value
                if not m.account_given:
                    m.account = m.id
            typo = typos.get(m.account) if m.account_given else None
            if typo is not None:
                message = f"typo: account {quoted(m.account)} -> {quoted(typo.value)}"
                run.report(m.line, m.account_field, message, typo)
                m.account = typo.value
        if group.leader is not None and group.leader in typos:
            typo = typos[group.leader]
            message = f"typo: leader {quoted(group.leader)} -> {quoted(typo.value)}"
            run.report(group.leader_line, group.leader_field, message, typo)
            group.leader = typo.value


def _apply_aliases(run: _Run, groups: list[RawGroup]) -> None:
    """A student's GitHub account by id; one that is already right is reported as confirmed.
    The corrections' own aliases come first; then the alias list's."""
    for group in groups:
        for m in group.members:
            alias = run.corr.aliases.get(m.id)
            if alias is None:
                _apply_listed(run, m)
                continue
            m.explained = True
            if m.account == alias.value:
                message = f"alias: account of {m.id} is already {quoted(alias.value)} (confirmed)"
                run.report(m.line, m.account_field, message, alias)
                continue
            message = f"alias: account of {m.id} {quoted(m.account)} -> {quoted(alias.value)}"
            run.report(m.line, m.account_field, message, alias)
            m.account = alias.value
            m.account_given = True


def _apply_listed(run: _Run, m: RawMember) -> None:
    """The alias list's account for a member, reported with the list's file and line; for a
    member known by GitHub login alone, the list's id for that account."""
    if m.login_only:
        by_account = {a.account.lower(): a for a in run.corr.listed_aliases.values()}
        alias = by_account.get(m.account.lower())
        if alias is not None:
            alias.matched = m.explained = True
            message = (
                f"id of GitHub login {quoted(m.account)}: {alias.id} [{alias.file}:{alias.line}]"
            )
            run.applied.append(Diagnostic(run.roster_file, m.line, m.field, message, "info"))
            m.id, m.login_only = alias.id, False
        return
    alias = run.corr.listed_aliases.get(m.id)
    if alias is None:
        return
    alias.matched = m.explained = True
    where = f"[{alias.file}:{alias.line}]"
    if m.account == alias.account:
        message = f"alias: account of {m.id} is already {quoted(alias.account)} (confirmed) {where}"
    else:
        message = f"alias: account of {m.id} {quoted(m.account)} -> {quoted(alias.account)} {where}"
        m.account = alias.account
        m.account_given = True
    run.applied.append(Diagnostic(run.roster_file, m.line, m.account_field, message, "info"))


def _rename_groups(run: _Run, groups: list[RawGroup]) -> None:
    """Group-name rules in file order; a rule that fails stops at that rule, not the build."""
    for rule in run.corr.group_names:
        for group in groups:
            new = _renamed(run, rule, group.name)
            if new is None:
                break
            if new != group.name:
                message = f"group name {quoted(group.name)} -> {quoted(new)}"
                run.report(group.line, group.field, message, rule)
                group.name = new


def _renamed(run: _Run, rule: NameRule, name: str) -> str | None:
    """``name`` after ``rule``, or None (with an error) when the rule timed out or is invalid."""
    try:
        if rule.regex is not None:
            return rule.regex.sub(rule.replacement, name, timeout=REGEX_TIMEOUT)
        return name.replace(rule.pattern, rule.replacement)
    except TimeoutError:
        run.problems.error(
            rule.line,
            rule.field,
            f"regex {quoted(rule.pattern)} took over {REGEX_TIMEOUT:g} s on the group "
            f"name {quoted(name)} (nested repeats like (x+)+ backtrack "
            "exponentially); the rule was not applied",
        )
    except (regex.error, re.error, IndexError) as exc:
        run.problems.error(
            rule.line, rule.field, f"replacement {quoted(rule.replacement)} is invalid: {exc}"
        )
    return None


def _set_leaders(run: _Run, groups: list[RawGroup]) -> None:
    """Leaders by final group name; the leader must be one of the group's members."""
    for group in groups:
        entry = run.corr.leaders.get(group.name)
        if entry is None:
            continue
        entry.matched = True
        ids = [m.id for m in group.members]
        if entry.value not in ids:
            run.problems.error(
                entry.line,
                entry.field,
                f"leader {quoted(entry.value)} is not a member of group {quoted(group.name)}",
            )
            continue
        before = group.leader or (ids[0] if ids else "")
        message = f"leader of {group.name}: {entry.value} (was {before})"
        run.report(group.line, group.field, message, entry)
        group.leader, group.leader_line = entry.value, entry.line
        group.leader_field, group.leader_file = entry.field, run.corr.file


def _note_expected_ids(run: _Run, groups: list[RawGroup]) -> None:
    """Ids that rightly look unlike the others: reported so the reason shows beside them."""
    for group in groups:
        for m in group.members:
            expected = run.corr.expected_ids.get(m.id)
            if expected is not None:
                message = f"id {quoted(m.id)} expected: {expected.value}"
                run.report(m.line, m.field, message, expected)


def _warn_unmatched(run: _Run) -> None:
    """An entry that changed nothing is stale or mistyped itself: a warning at its line. An
    alias list covers a whole class, most of it in other rosters: one info line for it."""
    listed = run.corr.listed_aliases.values()
    unused = [a for a in listed if not a.matched]
    if unused:
        first = min(unused, key=lambda a: a.line)
        run.applied.append(
            Diagnostic(
                first.file,
                first.line,
                "aliases",
                f"{len(unused)} of {len(listed)} aliases in the list name no student of "
                f"{run.roster_file} (first here)",
                "info",
            )
        )
    for entry in run.corr.entries():
        if entry.matched:
            continue
        if isinstance(entry, NameRule):
            what = f"{entry.kind} {quoted(entry.pattern)}"
        else:
            what = quoted(entry.key)
        message = f"correction {what} matched nothing in {run.roster_file}"
        run.problems.warning(entry.line, entry.field, message)


def find_corrections(roster: Path) -> Path | None:
    """The corrections file that sits next to a roster: `<stem>.corrections.yml` (or .yaml)."""
    for suffix in (".corrections.yml", ".corrections.yaml"):
        candidate = roster.with_name(roster.stem + suffix)
        if candidate.is_file():
            return candidate
    return None
