"""Import a cmsimde site (one ``config/content.htm``) into a sitegen ``content/`` tree.

cmsimde splits its single HTML file into pages at every H1, H2 and H3 and shows them in
document order, each heading nested under the last shallower one. We reproduce exactly that:
one Markdown file per heading; a heading with sub-headings becomes a folder whose
``index.md`` holds its own text. Numeric prefixes in the names *and* ``weight`` in the front
matter fix the order, so sitegen's depth-first walk (section page, then its children) yields
cmsimde's sequence of titles. Exact titles go in ``title:`` (duplicates are fine: the site
builder disambiguates slugs).

Everything is computed in memory first and written at the end into a temporary folder that
replaces DEST, so a failed import never leaves half a tree and the same input always gives
byte-identical output. The cut into pages is :mod:`sitegen.importers.cmsimde_pages`; links and
assets are :mod:`sitegen.importers.cmsimde_links`; this module reads, converts and writes.
"""

from __future__ import annotations

import bisect
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from sitegen.importers import mdtext
from sitegen.importers.cmsimde_links import Assets, LinkResolver
from sitegen.importers.cmsimde_pages import (
    Page,
    assign_paths,
    heading_markup,
    nest,
    split_pages,
    visible,
    walk_pages,
)
from sitegen.importers.html_to_markdown import Converter, Hooks
from sitegen.importers.htmltree import Element, ParseIssue, parse_html
from sitegen.importers.project_config import (
    CONFIG_NAME,
    ProjectConfig,
    detect_language,
    write_project_config,
)
from sitegen.importers.site_origin import missing_note, published_url
from sitegen.importers.youtube import poster, video_id


class CmsimdeImportError(Exception):
    """A problem that stops the import; printed by the CLI as ``file:line: message``."""

    def __init__(self, file: str | Path, line: int, message: str) -> None:
        super().__init__(f"{file}:{line}: {message}")
        self.file, self.line, self.message = str(file), line, message


@dataclass
class PageReport:
    """One produced page and what could not be carried over into it."""

    title: str
    path: str  # posix path relative to DEST
    level: int  # 1-3 as in cmsimde; 0 for the front page made from text before H1
    line: int  # line of the heading in content.htm
    warnings: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)  # what was changed on purpose, and why


@dataclass
class ImportReport:
    """What an import did. ``warnings`` holds every page's warnings as "title: message"."""

    source: Path
    dest: Path
    pages: list[PageReport] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    files_copied: list[str] = field(default_factory=list)  # DEST-relative paths
    images_extracted: list[str] = field(default_factory=list)  # DEST-relative paths
    config_file: Path | None = None  # the sitegen.yml written (or found) beside DEST
    config_note: str = ""  # what happened to it, for the report
    notes: list[str] = field(default_factory=list)  # site-wide changes made on purpose
    youtube_posters: int = 0  # YouTube iframes turned into click-to-load posters


@dataclass
class _Site:
    content_file: Path
    root: Path  # where config/ lives (or the file's folder for a bare content.htm)
    asset_bases: list[Path]  # folders that may hold images/, downloads/, static/


# -- locating and reading ---------------------------------------------------------------------


def _locate(path: Path) -> _Site:
    if path.is_dir():
        for candidate in (path / "config" / "content.htm", path / "content.htm"):
            if candidate.is_file():
                root = path
                break
        else:
            raise CmsimdeImportError(path, 0, "not a cmsimde site: no config/content.htm in it")
        content_file = candidate
    elif path.is_file():
        content_file = path
        root = path.parent.parent if path.parent.name == "config" else path.parent
    else:
        raise CmsimdeImportError(path, 0, "no such file or directory")
    return _Site(content_file, root, [root, root / "content"])


def _read(file: Path) -> str:
    try:
        data = file.read_bytes()
    except OSError as exc:
        raise CmsimdeImportError(file, 0, f"cannot read: {exc.strerror}") from None
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise CmsimdeImportError(file, line, "not valid UTF-8 (cmsimde writes UTF-8)") from None
    return text.replace("\r\n", "\n").replace("\r", "\n")


def _site_title(site: _Site) -> str | None:
    """The site title: ``config/sitetitle`` (the whole file, cmsimde from 2023 on), else
    ``siteTitle:...`` in ``config/config`` (earlier); None without either."""
    try:
        own = (site.root / "config" / "sitetitle").read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError):
        own = ""
    if own.strip():
        return " ".join(own.split())
    config = site.root / "config" / "config"
    try:
        lines = config.read_text(encoding="utf-8-sig").splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    for line in lines:
        key, _, value = line.partition(":")
        if key.strip() == "siteTitle" and value.strip():
            return value.strip()
    return None


# -- output ------------------------------------------------------------------------------------


def _page_text(title: str, weight: int | None, body: str) -> bytes:
    head = ["---", f"title: {mdtext.yaml_string(title)}"]
    if weight is not None:
        head.append(f"weight: {weight}")
    head.append("---")
    text = "\n".join(head) + "\n" + (f"\n{body}\n" if body.strip() else "")
    return text.encode("utf-8")


def _inside(child: Path, parent: Path) -> bool:
    try:
        child.resolve().relative_to(parent.resolve())
        return True
    except ValueError:
        return False


def _check_dest(dest: Path, site: _Site, force: bool) -> None:
    if dest.exists() and not dest.is_dir():
        raise CmsimdeImportError(dest, 0, "destination exists and is not a folder")
    guarded = [site.content_file] + [b / d for b in site.asset_bases for d in Assets.KINDS]
    for path in guarded:
        if path.exists() and _inside(path, dest):
            raise CmsimdeImportError(
                dest, 0, f"destination contains the site being imported ({path})"
            )
    if dest.exists() and any(dest.iterdir()):
        if not force:
            raise CmsimdeImportError(
                dest, 0, "destination is not empty (use --force to replace it)"
            )
        if (dest / ".git").exists():
            raise CmsimdeImportError(
                dest, 0, "refusing to replace a folder that holds a .git repository"
            )


def _write(dest: Path, files: dict[str, bytes], copies: dict[str, Path]) -> None:
    parent = dest.absolute().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{dest.name}.import-", dir=parent))
    except OSError as exc:
        raise CmsimdeImportError(dest, 0, f"cannot create: {exc.strerror}") from None
    try:
        for rel in sorted(files):
            target = tmp / rel
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(files[rel])
        for rel in sorted(copies):
            target = tmp / rel
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(copies[rel], target)
        if dest.exists():
            shutil.rmtree(dest)
        os.replace(tmp, dest)
    except OSError as exc:
        shutil.rmtree(tmp, ignore_errors=True)
        where = exc.filename or dest
        raise CmsimdeImportError(where, 0, f"cannot write: {exc.strerror or exc}") from None


# -- the import ---------------------------------------------------------------------------------


YOUTUBE = ("poster", "keep")  # what becomes of YouTube iframes (sitegen.importers.youtube)


def import_cmsimde(
    path: Path,
    dest: Path,
    *,
    force: bool = False,
    base_url: str | None = None,
    youtube: str = "poster",
) -> ImportReport:
    """Import the cmsimde site at ``path`` (a content.htm or a site folder) into ``dest``.

    ``base_url`` is the published address for ``sitegen.yml`` (default: from the site's
    GitHub remote when it has one; :mod:`sitegen.importers.site_origin`). ``youtube`` is
    "poster" (click-to-load, nothing loaded from YouTube before Play) or "keep".

    Raises :class:`CmsimdeImportError` for problems that stop the import; everything that
    was imported imperfectly is listed, page by page, in the returned report instead.
    """
    path, dest = Path(path), Path(dest)
    if youtube not in YOUTUBE:
        raise CmsimdeImportError(path, 0, f"youtube must be one of {', '.join(YOUTUBE)}")
    site = _locate(path)
    _check_dest(dest, site, force)
    published, origin_note = published_url(site.root, base_url)
    if published is None and origin_note:
        raise CmsimdeImportError("--base-url", 0, origin_note)
    origin_note = origin_note or missing_note()
    source = _read(site.content_file)
    root, issues = parse_html(source)
    preamble, flat = split_pages(root, issues)
    if not flat:
        raise CmsimdeImportError(
            site.content_file,
            1,
            "no <h1>, <h2> or <h3> with text: cmsimde needs at least one heading to make a page",
        )
    if flat[0].level != 1:  # cmsimde rewrites a first <h2>/<h3> into <h1> when it loads the file
        issues.append(
            ParseIssue(
                flat[0].line,
                f"first heading is <h{flat[0].level}>: made a top-level page, as cmsimde does",
            )
        )
        flat[0].level = 1
    issues.sort(key=lambda issue: issue.line)
    markup = heading_markup(root)
    tree = nest(flat)
    site_title = _site_title(site)
    front = Page(site_title or "Home", 0, 1, preamble) if visible(preamble) else None
    report = ImportReport(source=site.content_file, dest=dest)
    if front is not None:
        front.rel = PurePosixPath("index.md")
        assign_paths(tree, PurePosixPath("."))
        pages = list(walk_pages(tree))
    else:
        pages = _first_page_is_home(tree, report)
    language = detect_language([n.text() if isinstance(n, Element) else "" for n in root.children])

    assets = Assets(site.asset_bases)
    links = LinkResolver(pages, assets)
    per_page, site_warnings = _assign_issues(issues, pages, front)
    files: dict[str, bytes] = {}
    for page in ([front] if front else []) + pages:
        body, notes, done = _convert(page, links, assets, youtube, language)
        report.youtube_posters += sum("YouTube video" in n for _, n in done)
        notes.extend(per_page.get(id(page), []))
        if page.line in markup:
            tags = ", ".join(f"<{t}>" for t in markup[page.line])
            notes.append(
                (
                    page.line,
                    f"markup inside the heading not carried over ({tags}); title kept as text",
                )
            )
        notes.sort(
            key=lambda note: note[0] or 10**9
        )  # located notes in source order, then summaries
        if page is front:
            notes.insert(0, (0, "text before the first heading (cmsimde never shows it) kept here"))
        page_report = PageReport(page.title, page.rel.as_posix(), page.level, page.line)
        for line, message in notes:
            page_report.warnings.append(f"{message} (line {line})" if line else message)
        page_report.notes = [
            f"{m} (line {n})" if n else m for n, m in sorted(done, key=lambda note: note[0])
        ]
        report.warnings.extend(f"{page.title}: {w}" for w in page_report.warnings)
        report.pages.append(page_report)
        home = page is front or page.rel.as_posix() == "index.md"
        files[page.rel.as_posix()] = _page_text(page.title, None if home else page.weight, body)
    if (
        front is None and preamble
    ):  # only invisible things (scripts, comments) before the first heading
        _, notes, _ = _convert(Page("", 0, 1, preamble), links, assets, youtube, language)
        site_warnings.extend(
            f"before the first heading: {m}" + (f" (line {n})" if n else "") for n, m in notes
        )
    site_warnings.extend(assets.site_warnings())
    report.warnings.extend(f"{site.content_file.name}: {w}" for w in site_warnings)
    _import_extras(site.root, files, assets.copies, report)
    files.update(assets.extracted)
    report.files_copied = sorted(assets.copies)
    report.images_extracted = sorted(assets.extracted)
    _write(dest, files, assets.copies)
    _write_config(dest, site_title or pages[0].title, files, report, published)
    if origin_note:
        report.notes.append(origin_note)
    if report.youtube_posters:
        report.notes.append(
            f"{report.youtube_posters} YouTube iframe(s) became click-to-load posters: nothing "
            "is loaded from YouTube until a reader presses Play (youtube-nocookie.com); "
            "--youtube keep keeps the iframes as they were"
        )
    return report


def _first_page_is_home(tree: list[Page], report: ImportReport) -> list[Page]:
    """With no text before the first heading, the first page is the home page (cmsimde
    opens the site on it): it becomes ``index.md``, and the pages under it become top-level
    pages ahead of the rest, so the previous/next sequence stays cmsimde's. Returns every
    page in document order."""
    first, rest = tree[0], tree[1:]
    top = first.children + rest
    lifted = len(first.children)
    first.children = []
    # without sub-pages the others keep their numbers (02-, 03-...); with them, all renumber
    assign_paths(top if lifted else tree, PurePosixPath("."))
    first.rel = PurePosixPath("index.md")
    moved = f"; its {lifted} sub-page(s) are top-level pages" if lifted else ""
    report.notes.append(f"the first page, {first.title!r}, is the home page (index.md){moved}")
    return [first, *walk_pages(top)]


def _import_extras(root: Path, files: dict, copies: dict, report: ImportReport) -> None:
    """The blog's Pelican posts and the reveal decks, when the site has them."""
    from sitegen.importers.pelican import import_extras

    extras = import_extras(root)
    notes: dict[str, list[str]] = {}
    for file, message in extras.notes:
        notes.setdefault(file, []).append(message)
    for rel, data in extras.files.items():
        if rel in files:
            report.warnings.append(f"{rel}: not imported, a page of content.htm has this path")
            continue
        files[rel] = data
    for rel, path in extras.copies.items():
        copies.setdefault(rel, path)
    for title, rel in extras.posts + extras.decks:
        source = ("markdown/" if rel.startswith("blog/") else "reveal/") + rel.split("/", 1)[1]
        found = [f for f in notes if f.rsplit(".", 1)[0] == source.rsplit(".", 1)[0]]
        page = PageReport(title, rel, 0, 0, [m for f in found for m in notes.pop(f)])
        report.pages.append(page)
        report.warnings.extend(f"{title}: {w}" for w in page.warnings)
    for file, messages in notes.items():
        report.warnings.extend(f"{file}: {m}" for m in messages)


def _write_config(
    dest: Path, title: str, files: dict[str, bytes], report: ImportReport, base_url: str | None
) -> None:
    """``sitegen.yml`` beside DEST with the old site's title, its content's language and,
    when known, its published address."""
    texts = [data.decode("utf-8") for rel, data in sorted(files.items()) if rel.endswith(".md")]
    config = ProjectConfig(title, detect_language(texts), base_url=base_url)
    try:
        path, note, is_warning = write_project_config(dest, config, report.source.name)
    except OSError as exc:
        report.warnings.append(f"{CONFIG_NAME}: cannot write: {exc.strerror or exc}")
        return
    report.config_file = path
    report.config_note = note
    if is_warning:
        report.warnings.append(f"{CONFIG_NAME}: {note}")


def _convert(
    page: Page, links: LinkResolver, assets: Assets, youtube: str, language: str
) -> tuple[str, list[tuple[int, str]], list[tuple[int, str]]]:
    """Markdown for one page, its (line, message) warnings (line 0: page-wide) and its
    (line, message) notes of what was changed on purpose."""
    notes: list[tuple[int, str]] = []
    missing: list[str] = []
    assets.notes = done = []

    def warn(message: str, line: int) -> None:
        notes.append((line, message))

    def replace(el: Element) -> str | None:
        if youtube != "poster" or el.tag != "iframe":
            return None
        a = el.attrs
        html = poster(
            a.get("src", ""), a.get("title", ""), a.get("width", ""), a.get("height", ""), language
        )
        if html is not None:
            found = video_id(a.get("src", ""))
            done.append(
                (el.line, f"YouTube video {found[0] if found else ''} made a click-to-load poster")
            )
        return html

    hooks = Hooks(
        url=lambda url, el, attr: links.url(page, url, el, warn, missing),
        data_image=lambda uri, el: assets.data_image(page.rel, uri, el, warn),
        warn=warn,
        replace=replace,
    )
    body = Converter(hooks).convert(page.nodes)
    if missing:
        notes.append(
            (0, "missing file(s), linked but not copied: " + ", ".join(dict.fromkeys(missing)))
        )
    return body, notes, done


def _assign_issues(issues: list[ParseIssue], pages: list[Page], front: Page | None):
    """Give each markup problem to the page whose source it is in (by line)."""
    lines = [p.line for p in pages]
    per_page: dict[int, list[tuple[int, str]]] = {}
    site: list[str] = []
    for issue in issues:
        at = bisect.bisect_right(lines, issue.line) - 1
        owner = pages[at] if at >= 0 else front
        if owner is None:
            site.append(f"before the first heading: {issue.message} (line {issue.line})")
        else:
            per_page.setdefault(id(owner), []).append((issue.line, issue.message))
    return per_page, site


__all__ = ["CmsimdeImportError", "ImportReport", "PageReport", "import_cmsimde"]
