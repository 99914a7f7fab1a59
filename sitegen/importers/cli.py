"""``sitegen import cmsimde PATH [--dest DIR] [--force]``.

Exit status: 0 imported (warnings are listed, not fatal), 1 the import could not be done
(one line ``file:line: message``, line 0 meaning the file or folder as a whole), 2 usage.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from located.verbosity import add_verbosity
from sitegen.importers.cmsimde import CmsimdeImportError, ImportReport, import_cmsimde


def _parser(prog: str) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=prog, description="Import a site made with another tool.")
    sub = parser.add_subparsers(dest="kind", metavar="KIND", required=True)
    cms = sub.add_parser(
        "cmsimde",
        help="a cmsimde site: its config/content.htm, or the site folder",
        description="Split a cmsimde content.htm into one Markdown page per H1/H2/H3, "
        "copying referenced images and downloads.",
    )
    cms.add_argument("path", metavar="PATH", type=Path, help="content.htm or cmsimde site folder")
    cms.add_argument(
        "--dest",
        type=Path,
        default=Path("content"),
        help="folder to create (default: content); must be empty unless --force",
    )
    cms.add_argument("--force", action="store_true", help="replace DEST even if it is not empty")
    cms.add_argument(
        "--base-url",
        metavar="URL",
        help="where the site is published, e.g. https://USER.github.io/REPO/ (written to "
        "sitegen.yml; default: from the site's GitHub remote, if it has one)",
    )
    cms.add_argument(
        "--youtube",
        choices=("poster", "keep"),
        default="poster",
        help="YouTube iframes: a click-to-load poster that loads nothing from YouTube until "
        "played (default), or keep them as they were",
    )
    add_verbosity(
        cms,
        "print only the warnings, each with its page",
        "also list every file copied and image extracted",
    )
    return parser


def format_report(report: ImportReport, verbosity: int = 0) -> str:
    """A summary line, then every page with the warnings that belong to it. Quiet
    (``verbosity`` < 0): only the warnings, each named with its page; verbose: also every
    file copied and image extracted."""
    if verbosity < 0:
        quiet = [f"{page.path}: {w}" for page in report.pages for w in page.warnings]
        paged = sum(len(p.warnings) for p in report.pages)
        quiet.extend(f"site: {w}" for w in report.warnings[paged:])
        return "\n".join(quiet)
    warnings = sum(len(p.warnings) for p in report.pages)
    site_level = len(report.warnings) - warnings
    lines = [
        f"Imported {len(report.pages)} page(s) from {report.source} into {report.dest}",
        f"  {len(report.files_copied)} file(s) copied, {len(report.images_extracted)} embedded "
        f"image(s) extracted, {len(report.warnings)} warning(s)",
        "",
    ]
    for page in report.pages:
        parts = page.path.split("/")
        depth = len(parts) - 1 - (1 if parts[-1] == "index.md" and len(parts) > 1 else 0)
        indent = "  " * depth
        lines.append(f"  {indent}{page.path}  [{page.title}]")
        lines.extend(f"  {indent}    ! {w}" for w in page.warnings)
        lines.extend(f"  {indent}    - {n}" for n in page.notes)
    if report.config_note:
        lines.append("")
        lines.append(f"Settings: {report.config_note}")
    if report.notes:
        lines.append("")
        lines.append("Notes:")
        lines.extend(f"    - {n}" for n in report.notes)
    if site_level:
        lines.append("")
        lines.append("Site:")
        lines.extend(f"    ! {w}" for w in report.warnings[-site_level:])
    if verbosity > 0 and (report.files_copied or report.images_extracted):
        lines.append("")
        lines.extend(f"copied {f}" for f in report.files_copied)
        lines.extend(f"extracted {f}" for f in report.images_extracted)
    return "\n".join(lines)


def main(argv: list[str] | None = None, prog: str = "sitegen import") -> int:
    """Run the import command; returns the exit status instead of exiting."""
    parser = _parser(prog)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse exits 2 on usage errors, 0 for --help
        return int(exc.code or 0)
    try:
        report = import_cmsimde(
            args.path, args.dest, force=args.force, base_url=args.base_url, youtube=args.youtube
        )
    except CmsimdeImportError as exc:
        print(f"{exc.file}:{exc.line}: {exc.message}", file=sys.stderr)
        return 1
    try:
        text = format_report(report, args.verbosity)
        if text:
            print(text)
        sys.stdout.flush()
    except BrokenPipeError:  # piped into `head`: the import itself is done
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
