"""`load_roster`: read, parse, correct, validate and freeze a roster in one call.

This is the one entry point the site pipeline and the CLI use, so that both see
the same roster and the same diagnostics for the same files.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path
from typing import Literal

from .aliases import load_aliases
from .corrections import Corrections, apply_corrections, find_corrections, load_corrections
from .detect import LAYOUTS
from .model import (
    DEFAULT_MARKS,
    WHOLE_FILE,
    Group,
    MarkRule,
    Member,
    Roster,
    RosterError,
    RosterResult,
)
from .parse_csv import parse_csv
from .parse_text import parse_text
from .parse_yaml import parse_yaml
from .records import Collector, RawGroup
from .source import decode, detect_format, read_bytes
from .validate import slug_for, validate

PARSERS = {"tsv": parse_text, "csv": parse_csv, "yaml": parse_yaml}

PathLike = str | os.PathLike[str]


def load_roster(
    path: PathLike,
    corrections: PathLike | None | Literal[False] = None,
    course_repo: str = "cd2021",
    layout: str = "auto",
    marks: Iterable[str] | None = None,
    aliases: PathLike | None = None,
) -> RosterResult:
    """Load a roster file (.txt/.tsv, .csv, .yml/.yaml) with optional corrections.

    `corrections=None` uses `<roster stem>.corrections.yml` next to the roster if
    one exists (reported as info); `False` disables that. `layout` is for
    text files: "auto" (detect from the content; `roster.detect`) or one of
    `roster.detect.TEXT_LAYOUTS`. `marks` lists the mark words (default: the corrections
    file's `marks:` keys, else `X`). `aliases` names an id -> account list
    (`roster.aliases`) applied like the corrections' aliases, which win over it. Raises
    RosterError only when a file cannot be read, has
    an unsupported type or an unknown layout is asked for; everything wrong with the
    content is in `result.diagnostics` (check `result.errors`).
    """
    roster_path = Path(path)
    file = str(roster_path)
    fmt = detect_format(roster_path)
    if layout not in LAYOUTS:
        raise RosterError(
            file,
            WHOLE_FILE,
            "layout",
            f"unknown layout {layout!r} (use one of {', '.join(LAYOUTS)})",
        )
    if layout != "auto" and fmt != "tsv":
        raise RosterError(
            file,
            WHOLE_FILE,
            "layout",
            f"layout {layout!r} applies to text rosters (.txt, .tsv)",
        )
    source = decode(read_bytes(roster_path), file, fmt)

    notes: list[tuple[str, str]] = []
    corrections_path: Path | None = None
    if corrections is None:
        corrections_path = find_corrections(roster_path)
        if corrections_path is not None:
            notes.append(
                (
                    "corrections",
                    f"using corrections file {corrections_path} found next to the roster",
                )
            )
    elif corrections is not False:
        corrections_path = Path(corrections)
    corr = None
    extra = []
    if corrections_path is not None:
        corr, corr_diags = load_corrections(corrections_path)
        extra.extend(corr_diags)
        if any(d.severity == "error" for d in corr_diags):
            corr = None
    rules = {r.word: r for r in DEFAULT_MARKS}
    if corr is not None and corr.marks:
        rules = dict(corr.marks)
    if marks is not None:
        rules = {w: rules.get(w) or MarkRule(w) for w in marks}

    c = Collector(file, frozenset(rules))
    for where, message in notes:
        c.info(WHOLE_FILE, where, message)
    c.diagnostics.extend(source.diagnostics)
    if fmt == "tsv":
        groups = parse_text(source.lines, c, layout)
    else:
        groups = PARSERS[fmt](source.lines, c)

    applied = []
    expected_ids: set[str] = set()
    unusable = corrections_path is not None and corr is None
    if aliases is not None:
        listed, alias_diags = load_aliases(aliases)
        extra.extend(alias_diags)
        corr = corr or Corrections(str(aliases))  # the list alone: no (usable) corrections
        corr.listed_aliases = listed
    if unusable:
        _unusable_corrections(c, corrections_path)
    if corr is not None:
        applied, problems = apply_corrections(groups, corr, file)
        extra.extend(problems)
        expected_ids = set(corr.expected_ids)

    if not groups and not any(d.severity == "error" for d in c.diagnostics):
        c.error(1, "file", "no groups found in the roster")
    validate(groups, c, course_repo, expected_ids)
    diagnostics = c.finish() + extra
    # Roster findings first, in file order; then the corrections file's. Stable within a line.
    diagnostics.sort(key=lambda d: (d.file != file, d.file, d.line or 0))
    return RosterResult(
        roster=freeze(groups),
        diagnostics=diagnostics,
        corrections_applied=applied,
        file=file,
        corrections_file=str(corrections_path) if corrections_path else None,
        aliases_file=str(aliases) if aliases is not None else None,
        course_repo=course_repo,
        format=fmt,
        layout=c.layout,
        mark_rules=rules,
    )


def _unusable_corrections(c: Collector, path: Path | None) -> None:
    message = f"corrections file {path} has errors; no corrections applied"
    c.error(WHOLE_FILE, "corrections", message)


def freeze(groups: list[RawGroup]) -> Roster:
    """Turn corrected raw groups into the immutable public model."""
    frozen = []
    for g in groups:
        members = tuple(
            Member(m.id, m.account, m.notes, m.line, m.field, m.marks) for m in g.members
        )
        leader = g.leader if g.leader is not None else (members[0].id if members else "")
        frozen.append(Group(g.name, slug_for(g.name), leader, members, g.line))
    return Roster(tuple(frozen))
