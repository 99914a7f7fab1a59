"""`load_roster`: read, parse, correct, validate and freeze a roster in one call.

This is the one entry point the site pipeline and the CLI use, so that both see
the same roster and the same diagnostics for the same files.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Literal

from .corrections import apply_corrections, find_corrections, load_corrections
from .model import Group, Member, Roster, RosterResult
from .parse_csv import parse_csv
from .parse_tsv import parse_tsv
from .parse_yaml import parse_yaml
from .records import Collector, RawGroup
from .source import decode, detect_format, read_bytes
from .validate import slug_for, validate

PARSERS = {"tsv": parse_tsv, "csv": parse_csv, "yaml": parse_yaml}

PathLike = str | os.PathLike[str]


def load_roster(
    path: PathLike,
    corrections: PathLike | None | Literal[False] = None,
    course_repo: str = "cd2021",
) -> RosterResult:
    """Load a roster file (.txt/.tsv, .csv, .yml/.yaml) with optional corrections.

    `corrections=None` uses `<roster stem>.corrections.yml` next to the roster if
    one exists (reported as info); `False` disables that. Raises RosterError only
    when a file cannot be read or has an unsupported type; everything wrong with
    the content is in `result.diagnostics` (check `result.errors`).
    """
    roster_path = Path(path)
    file = str(roster_path)
    fmt = detect_format(roster_path)
    source = decode(read_bytes(roster_path), file, fmt)
    c = Collector(file)
    c.diagnostics.extend(source.diagnostics)
    groups = PARSERS[fmt](source.lines, c)

    corrections_path: Path | None = None
    if corrections is None:
        corrections_path = find_corrections(roster_path)
        if corrections_path is not None:
            c.info(
                0,
                "corrections",
                f"using corrections file {corrections_path} found next to the roster",
            )
    elif corrections is not False:
        corrections_path = Path(corrections)
    applied = []
    extra = []
    expected_ids: set[str] = set()
    if corrections_path is not None:
        corr, corr_diags = load_corrections(corrections_path)
        extra.extend(corr_diags)
        if not any(d.severity == "error" for d in corr_diags):
            applied, problems = apply_corrections(groups, corr, file)
            extra.extend(problems)
            expected_ids = set(corr.expected_ids)
        else:
            c.error(
                0,
                "corrections",
                f"corrections file {corrections_path} has errors; no corrections applied",
            )

    if not groups and not any(d.severity == "error" for d in c.diagnostics):
        c.error(1, "file", "no groups found in the roster")
    validate(groups, c, course_repo, expected_ids)
    diagnostics = c.finish() + extra
    # Roster findings first, in file order; then the corrections file's. Stable within a line.
    diagnostics.sort(key=lambda d: (d.file != file, d.file, d.line))
    return RosterResult(
        roster=freeze(groups),
        diagnostics=diagnostics,
        corrections_applied=applied,
        file=file,
        corrections_file=str(corrections_path) if corrections_path else None,
        course_repo=course_repo,
        format=fmt,
    )


def freeze(groups: list[RawGroup]) -> Roster:
    """Turn corrected raw groups into the immutable public model."""
    frozen = []
    for g in groups:
        members = tuple(Member(m.id, m.account, m.notes, m.line, m.field) for m in g.members)
        leader = g.leader if g.leader is not None else (members[0].id if members else "")
        frozen.append(Group(g.name, slug_for(g.name), leader, members, g.line))
    return Roster(tuple(frozen))
