"""Alias lists: a student id -> GitHub account list kept apart from the groups (the course in 2020).

The teacher collected the students' GitHub accounts once a year in a file of its own (one
`id<TAB>account` a line, often under a `學號 / github 帳號` header) and the grouping files
listed ids only; the scripts looked each id up in that list (`realA`). Given to
`load_roster(..., aliases=FILE)` (`--aliases FILE`, `aliases:` on a roster in sitegen.yml),
every entry is an alias, as if written under `aliases:` in the corrections file; the
corrections' own aliases win over the list (they are the specific fix).

Accepted files: text (`id account` a line, tabs or spaces, optional header; or any roster in
the one-member-a-line layout, its account column taken), CSV with id and account columns,
and YAML (`{id: account}`, or the same under an `aliases:` key).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import yaml

from .detect import clean, detect, split_fields
from .labels import column_role, id_like
from .model import Diagnostic, quoted
from .records import Collector, make_member
from .source import decode, detect_format, read_bytes
from .yamlnodes import ROOT, Walker, compose, line_of


@dataclass
class Alias:
    """One listed account and where it was written."""

    id: str
    account: str
    file: str
    line: int
    matched: bool = False


def load_aliases(path: str | Path) -> tuple[dict[str, Alias], list[Diagnostic]]:
    """Read an alias list; raises RosterError only when the file cannot be read."""
    path = Path(path)
    file = str(path)
    fmt = detect_format(path)
    source = decode(read_bytes(path), file, fmt)
    c = Collector(file)
    c.diagnostics.extend(source.diagnostics)
    pairs: list[tuple[int, str, str | None]] = []  # (line, id, account as written)
    if fmt == "yaml":
        _yaml_pairs(source.text, c, pairs)
    elif fmt == "csv":
        _csv_pairs(source.lines, c, pairs)
    else:
        _text_pairs(source.lines, c, pairs)
    out: dict[str, Alias] = {}
    for line, sid, account in pairs:
        member = make_member(c, sid, account, line, "id", "account", missing_account=None)
        if member is None or not member.account_given:
            continue
        seen = out.get(member.id)
        if seen is not None and seen.account != member.account:
            c.error(
                line,
                "id",
                f"{member.id} is listed twice with different accounts: "
                f"{quoted(seen.account)} (line {seen.line}) and {quoted(member.account)}",
            )
            continue
        out.setdefault(member.id, Alias(member.id, member.account, file, line))
    if not out and not c.diagnostics:
        c.error(1, "file", "no id -> account pairs found (expected id<TAB>account lines)")
    return out, c.finish()


def _text_pairs(lines: list[str], c: Collector, pairs: list) -> None:
    found = detect(lines, c)
    if found.layout == "rows" and found.columns and found.columns.account is not None:
        cols = found.columns
        id_col, acc_col = cols.id, cols.account
    elif found.layout == "accounts":
        id_col, acc_col = 0, 1
    else:
        c.error(
            1,
            "aliases",
            "not an alias list: expected one 'id<TAB>account' a line (or a roster with an "
            "account column)",
        )
        return
    for number, text in enumerate(lines, 1):
        fields = split_fields(text, c.mark_words)
        if not fields:
            continue
        if len(fields) <= id_col or not id_like(clean(fields[id_col], c)):
            if not pairs:  # a header or a title above the list
                c.info(number, "line", f"header line skipped: {quoted(text.strip())}")
                continue
        account = fields[acc_col] if acc_col < len(fields) else None
        pairs.append((number, fields[id_col] if id_col < len(fields) else "", account))


def _csv_pairs(lines: list[str], c: Collector, pairs: list) -> None:
    rows = list(csv.reader(line + "\n" for line in lines))
    header = next((i for i, row in enumerate(rows) if any(c_.strip() for c_ in row)), None)
    roles = [column_role(cell) for cell in rows[header]] if header is not None else []
    if header is None or "id" not in roles or "account" not in roles:
        c.error(1, "header", "an alias list in CSV needs a header with id and account columns")
        return
    id_col, acc_col = roles.index("id"), roles.index("account")
    for i, row in enumerate(rows[header + 1 :], header + 2):
        if len(row) > id_col and row[id_col].strip():
            pairs.append((i, row[id_col], row[acc_col] if len(row) > acc_col else None))


def _yaml_pairs(text: str, c: Collector, pairs: list) -> None:
    root = compose(text, c)
    if root is None:
        return
    w = Walker(c)
    if isinstance(root, yaml.MappingNode) and [k.value for k, _ in root.value] == ["aliases"]:
        root = root.value[0][1]
    for key, key_node, value in w.mapping(root, ROOT):
        account = w.text(value, key)
        if account is not None:
            pairs.append((line_of(key_node), key, account))
