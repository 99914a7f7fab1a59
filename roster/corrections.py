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
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from .model import Diagnostic, quoted
from .records import Collector, RawGroup
from .source import decode, read_bytes
from .yamlnodes import ROOT, Node, Walker, compose, line_of

KEYS = ("typos", "aliases", "group_names", "leaders", "expected_ids")


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
    regex: re.Pattern[str] | None = None
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
                v = w.scalar(v_node, f"{key}.{k}")
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
        text = w.scalar(value, f"{where}.{key}", allow_empty=(key == "with"))
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
            rule.regex = re.compile(found[kind])
        except re.error as exc:
            c.error(line, f"{where}.regex", f"invalid regular expression: {exc}")
            return None
    return rule


def apply_corrections(
    groups: list[RawGroup], corr: Corrections, roster_file: str
) -> tuple[list[Diagnostic], list[Diagnostic]]:
    """Apply corrections in place. Returns (corrections applied, problems found)."""
    applied: list[Diagnostic] = []
    problems = Collector(corr.file)

    def report(line: int, where: str, message: str, entry: Entry | NameRule) -> None:
        entry.matched = True
        applied.append(
            Diagnostic("info", roster_file, line, where, f"{message} [{corr.file}:{entry.line}]")
        )

    for group in groups:
        for m in group.members:
            typo = corr.typos.get(m.id)
            if typo is not None:
                report(m.line, m.field, f"typo: id {quoted(m.id)} -> {quoted(typo.value)}", typo)
                m.id = typo.value
                if not m.account_given:
                    m.account = m.id
            typo = corr.typos.get(m.account) if m.account_given else None
            if typo is not None:
                report(
                    m.line,
                    m.account_field,
                    f"typo: account {quoted(m.account)} -> {quoted(typo.value)}",
                    typo,
                )
                m.account = typo.value
        if group.leader is not None and group.leader in corr.typos:
            typo = corr.typos[group.leader]
            report(
                group.leader_line,
                group.leader_field,
                f"typo: leader {quoted(group.leader)} -> {quoted(typo.value)}",
                typo,
            )
            group.leader = typo.value

    for group in groups:
        for m in group.members:
            alias = corr.aliases.get(m.id)
            if alias is None:
                continue
            m.explained = True
            if m.account == alias.value:
                report(
                    m.line,
                    m.account_field,
                    f"alias: account of {m.id} is already {quoted(alias.value)} (confirmed)",
                    alias,
                )
            else:
                report(
                    m.line,
                    m.account_field,
                    f"alias: account of {m.id} {quoted(m.account)} -> {quoted(alias.value)}",
                    alias,
                )
                m.account = alias.value
                m.account_given = True

    for rule in corr.group_names:
        for group in groups:
            try:
                if rule.regex is not None:
                    new = rule.regex.sub(rule.replacement, group.name)
                else:
                    new = group.name.replace(rule.pattern, rule.replacement)
            except (re.error, IndexError) as exc:
                problems.error(
                    rule.line,
                    rule.field,
                    f"replacement {quoted(rule.replacement)} is invalid: {exc}",
                )
                break
            if new != group.name:
                report(
                    group.line,
                    group.field,
                    f"group name {quoted(group.name)} -> {quoted(new)}",
                    rule,
                )
                group.name = new

    for group in groups:
        entry = corr.leaders.get(group.name)
        if entry is None:
            continue
        entry.matched = True
        ids = [m.id for m in group.members]
        if entry.value not in ids:
            problems.error(
                entry.line,
                entry.field,
                f"leader {quoted(entry.value)} is not a member of group {quoted(group.name)}",
            )
            continue
        before = group.leader or (ids[0] if ids else "")
        report(
            group.line, group.field, f"leader of {group.name}: {entry.value} (was {before})", entry
        )
        group.leader, group.leader_line, group.leader_field, group.leader_file = (
            entry.value,
            entry.line,
            entry.field,
            corr.file,
        )

    for group in groups:
        for m in group.members:
            expected = corr.expected_ids.get(m.id)
            if expected is not None:
                report(m.line, m.field, f"id {quoted(m.id)} expected: {expected.value}", expected)

    for entry in corr.entries():
        if not entry.matched:
            what = (
                f"{entry.kind} {quoted(entry.pattern)}"
                if isinstance(entry, NameRule)
                else quoted(entry.key)
            )
            problems.warning(
                entry.line, entry.field, f"correction {what} matched nothing in {roster_file}"
            )
    return applied, problems.finish()


def find_corrections(roster: Path) -> Path | None:
    """The corrections file that sits next to a roster: `<stem>.corrections.yml` (or .yaml)."""
    for suffix in (".corrections.yml", ".corrections.yaml"):
        candidate = roster.with_name(roster.stem + suffix)
        if candidate.is_file():
            return candidate
    return None
