"""Command line: `sitegen roster check|links|diff ...` (also `python -m roster`).

Exit codes: 0 fine (warnings allowed), 1 the roster has errors or a file could
not be read, 2 usage error. Problems are printed one per line as
`file:line: severity: field: message` (`located.diagnostics`), never as a traceback,
because the people running this are teachers fixing a spreadsheet, not debugging Python.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TextIO

from located.verbosity import add_verbosity

from .detect import LAYOUTS
from .diff import diff
from .emit import to_csv, to_html, to_json
from .load import load_roster
from .model import WHOLE_FILE, Diagnostic, RosterError, RosterResult, printable

EMITTERS: dict[str, Callable[[RosterResult], str]] = {
    "html": to_html,
    "json": to_json,
    "csv": to_csv,
}


def _add_input_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", help="roster file (.txt/.tsv, .csv, .yml/.yaml)")
    group = p.add_mutually_exclusive_group()
    group.add_argument(
        "--corrections",
        metavar="F",
        help="corrections YAML (default: <roster stem>.corrections.yml next to the roster)",
    )
    group.add_argument(
        "--no-corrections", action="store_true", help="do not look for a corrections file"
    )
    p.add_argument(
        "--course-repo",
        metavar="R",
        default="cd2021",
        help="members' course repository (default: cd2021)",
    )
    p.add_argument(
        "--layout",
        choices=LAYOUTS,
        default="auto",
        help="text layout: paired (group, id, account, ...), ids (group, ids), rows (one "
        "member a line with a group column), blocks (a group label line, then ids), "
        "lists (Python lists), or auto (detect; the default)",
    )
    p.add_argument(
        "--aliases",
        metavar="FILE",
        help="an id -> GitHub account list (id<TAB>account lines, CSV or YAML) applied as "
        "aliases; the corrections file's own aliases win",
    )
    p.add_argument(
        "--marks",
        metavar="WORDS",
        help="comma-separated mark words beside ids or accounts "
        "(default: the corrections file's marks, else X)",
    )


def _add_verbosity(p: argparse.ArgumentParser) -> None:
    add_verbosity(p, "print only warnings, errors and the command's data", "more detail")


def build_parser(prog: str) -> argparse.ArgumentParser:
    """The argument parser (exposed so `sitegen` can show its help)."""
    parser = argparse.ArgumentParser(
        prog=prog, description="Check course rosters and print group/member links."
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    check = sub.add_parser("check", help="show groups, members, corrections, warnings and errors")
    _add_input_options(check)
    _add_verbosity(check)
    links = sub.add_parser("links", help="print group and member links")
    _add_input_options(links)
    _add_verbosity(links)
    links.add_argument(
        "--format", choices=sorted(EMITTERS), default="html", help="output format (default: html)"
    )
    changes = sub.add_parser(
        "diff", help="what changed between two rosters (roster files or links JSON)"
    )
    changes.add_argument("old", help="older roster file or JSON from 'links --format json'")
    changes.add_argument("new", help="newer roster file or JSON")
    _add_verbosity(changes)
    return parser


def _load(args: argparse.Namespace, file: str | None = None) -> RosterResult:
    corrections = (
        False if getattr(args, "no_corrections", False) else getattr(args, "corrections", None)
    )
    marks = getattr(args, "marks", None)
    return load_roster(
        file or args.file,
        corrections=corrections,
        course_repo=getattr(args, "course_repo", "cd2021"),
        layout=getattr(args, "layout", "auto"),
        marks=[w.strip() for w in marks.split(",") if w.strip()] if marks is not None else None,
        aliases=getattr(args, "aliases", None),
    )


def _n(count: int, word: str) -> str:
    return f"{count} {word}{'' if count == 1 else 's'}"


def _section(out: TextIO, title: str, items: list[Diagnostic]) -> None:
    if items:
        print(f"{title} ({len(items)}):", file=out)
        for d in items:
            print(f"  {d}", file=out)


def _check(args: argparse.Namespace, out: TextIO) -> int:
    """Print the roster as read. Every value from the files goes through `printable`, so a
    roster cannot send escape sequences to the terminal."""
    result = _load(args)
    groups = result.roster.groups
    p = printable
    kind = f"{result.format}, {result.layout} layout" if result.layout else result.format
    if args.verbosity < 0:  # quiet: the problems and the verdict only
        _section(out, "warnings", result.warnings)
        _section(out, "errors", result.errors)
        _verdict(out, result)
        return 1 if result.errors else 0
    print(
        f"roster: {p(result.file)} ({kind}): {_n(len(groups), 'group')}, "
        f"{_n(len(result.roster.members), 'member')}",
        file=out,
    )
    print(f"corrections: {p(result.corrections_file or 'none')}", file=out)
    if result.aliases_file:
        print(f"aliases: {p(result.aliases_file)}", file=out)
    for g in groups:
        print(
            f"{p(g.name)}  (slug {p(g.slug)}, leader {p(g.leader or '-')}, "
            f"{_n(len(g.members), 'member')}, line {g.line})",
            file=out,
        )
        for m in g.members:
            marks = "".join(
                f"  <{p(r.word)}{': ' + p(r.meaning) if r.meaning else ''}"
                f"{'' if r.links else ', not linked'}>"
                for r in result.marks_of(m)
            )
            notes = f"  [{p('; '.join(m.notes))}]" if m.notes else ""
            print(f"  {p(m.id)}  {p(m.account)}{marks}{notes}", file=out)
    _section(out, "corrections applied", result.corrections_applied)
    if args.verbosity > 0:
        _section(out, "info", result.infos)
    _section(out, "warnings", result.warnings)
    _section(out, "errors", result.errors)
    _verdict(out, result)
    return 1 if result.errors else 0


def _verdict(out: TextIO, result: RosterResult) -> None:
    print(
        f"{'FAILED' if result.errors else 'OK'}: {_n(len(result.errors), 'error')}, "
        f"{_n(len(result.warnings), 'warning')}",
        file=out,
    )


def _links(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    result = _load(args)
    for d in result.warnings + result.errors:
        print(d, file=err)
    if result.errors:
        print(f"{len(result.errors)} errors; no links printed", file=err)
        return 1
    out.write(EMITTERS[args.format](result))
    if args.verbosity > 0:
        roster = result.roster
        print(
            f"{printable(result.file)}: {_n(len(roster.groups), 'group')}, "
            f"{_n(len(roster.members), 'member')}, corrections: "
            f"{printable(result.corrections_file or 'none')}",
            file=err,
        )
    return 0


def _as_dict(file: str, err: TextIO) -> dict | None:
    if Path(file).suffix.lower() == ".json":
        try:
            data = json.loads(Path(file).read_text(encoding="utf-8"))
        except OSError as exc:
            raise RosterError(
                file, WHOLE_FILE, "file", f"cannot read: {exc.strerror or exc}"
            ) from None
        except (UnicodeDecodeError, json.JSONDecodeError) as exc:
            line = getattr(exc, "lineno", WHOLE_FILE)
            raise RosterError(file, line, "file", f"not roster JSON: {exc}") from None
        if not isinstance(data, dict) or not isinstance(data.get("groups"), list):
            raise RosterError(
                file, 1, "groups", "not roster JSON: expected an object with a 'groups' list"
            )
        return data
    result = load_roster(file)
    for d in result.errors:
        print(d, file=err)
    return None if result.errors else result.to_dict()


def _diff(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    old, new = _as_dict(args.old, err), _as_dict(args.new, err)
    if old is None or new is None:
        return 1
    lines = diff(old, new)
    for line in lines:
        print(printable(line), file=out)
    if not lines and args.verbosity >= 0:
        print("no changes", file=out)
    if args.verbosity > 0:
        print(f"{_n(len(lines), 'change')}", file=err)
    return 0


def main(argv: list[str] | None = None, prog: str = "sitegen roster") -> int:
    """Run the roster CLI; returns the exit code instead of exiting."""
    out, err = sys.stdout, sys.stderr
    parser = build_parser(prog)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse exits 2 on usage errors and 0 for --help
        return exc.code if isinstance(exc.code, int) else 2
    try:
        if args.command == "check":
            return _check(args, out)
        if args.command == "links":
            return _links(args, out, err)
        return _diff(args, out, err)
    except RosterError as exc:
        print(exc, file=err)
        return 1
    except BrokenPipeError:  # e.g. `... links FILE | head`: stop quietly, as other tools do
        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError):
            pass
        return 0
    except Exception as exc:  # a bug in roster: still one line, never a traceback
        print(f"{prog}: internal error: {type(exc).__name__}: {printable(str(exc))}", file=err)
        return 1
