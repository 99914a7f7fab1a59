"""The two other parts of a cmsimde site: Pelican blog posts and reveal.js slide decks.

cmsimde keeps the blog as Pelican Markdown in ``markdown/*.md`` (metadata lines ``Title:``,
``Date:``, ``Tags:``, ``Category:``, ``Slug:``, ``Author:``, ``Summary:`` above a blank
line) and the weekly-report decks in ``reveal/``. Posts become ``blog/NAME.md`` with front
matter (sitegen.blog); decks become ``slides/NAME.md`` with ``---`` between slides, ``--``
between vertical ones and ``Note:`` for speaker notes (sitegen.slides). A deck that cannot be
read as reveal sections is copied as it is and reported, never dropped.
"""

from __future__ import annotations

import re
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

from sitegen.importers import mdtext
from sitegen.importers.html_inline import Hooks
from sitegen.importers.html_to_markdown import Converter
from sitegen.importers.htmltree import Element, parse_html
from sitegen.post_dates import parse_post_date

_META = re.compile(r"^([A-Za-z][A-Za-z_]*):[ \t]*(.*?)[ \t]*$")
_PELICAN_LINK = re.compile(r"\{(?:static|filename|attach)\}/?")
_KNOWN = {"title", "date", "modified", "tags", "category", "slug", "author", "authors"}
_KNOWN |= {"summary", "status", "lang"}
_HEADING = re.compile(r"^h([1-6])$")


@dataclass
class Imported:
    """What came along: written files (DEST-relative) and (file, message) notes."""

    files: dict[str, bytes] = field(default_factory=dict)
    copies: dict[str, Path] = field(default_factory=dict)
    posts: list[tuple[str, str]] = field(default_factory=list)  # (title, path)
    decks: list[tuple[str, str]] = field(default_factory=list)
    notes: list[tuple[str, str]] = field(default_factory=list)


def import_extras(root: Path) -> Imported:
    """Posts from ``root/markdown`` and decks from ``root/reveal``, when those exist."""
    out = Imported()
    posts = root / "markdown"
    if posts.is_dir():
        for path in sorted(posts.glob("*.md")):
            _post(path, out)
    decks = root / "reveal"
    if decks.is_dir():
        for path in sorted(p for p in decks.iterdir() if p.suffix in (".html", ".md")):
            if path.name == "index.html" and not _slides_div(path):
                continue  # reveal's own start page, not a deck
            _deck(path, out)
    return out


# -- Pelican posts --------------------------------------------------------------------------


def parse_pelican(text: str) -> tuple[dict[str, tuple[str, int]], str, int]:
    """(key -> (value, line)), body, the body's first line. Keys are lower-cased."""
    lines = text.replace("\r\n", "\n").split("\n")
    meta: dict[str, tuple[str, int]] = {}
    i = 0
    while i < len(lines) and lines[i].strip():
        m = _META.match(lines[i])
        if not m:
            break
        meta[m.group(1).lower()] = (m.group(2), i + 1)
        i += 1
    while i < len(lines) and not lines[i].strip():
        i += 1
    return meta, "\n".join(lines[i:]), i + 1


def _post(path: Path, out: Imported) -> None:
    name = f"markdown/{path.name}"
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        out.notes.append((name, f"not imported: cannot read ({exc})"))
        return
    meta, body, _ = parse_pelican(text)
    title = meta.get("title", (path.stem, 0))[0]
    head = ["---", f"title: {mdtext.yaml_string(title)}"]
    raw_date, line = meta.get("date", ("", 0))
    date = parse_post_date(raw_date.replace("/", "-")) if raw_date else None
    if date is None:
        why = f"Date '{raw_date}' (line {line}) is not a date" if raw_date else "no Date:"
        out.notes.append((name, f"{why}: fill in date: before building"))
        head.append(f"date: {mdtext.yaml_string(raw_date or 'YYYY-MM-DD')}")
    else:
        head.append(f"date: {mdtext.yaml_string(date.replace('T', ' '))}")
    tags = [t.strip() for t in meta.get("tags", ("", 0))[0].split(",") if t.strip()]
    category = meta.get("category", ("", 0))[0].strip()
    if category and category not in tags:
        tags.append(category)  # sitegen has tags only: the category becomes one
    if tags:
        head.append("tags: [" + ", ".join(mdtext.yaml_string(t) for t in tags) + "]")
    for key in ("summary", "slug"):
        if meta.get(key, ("", 0))[0]:
            head.append(f"{key}: {mdtext.yaml_string(meta[key][0])}")
    if meta.get("status", ("", 0))[0].lower() == "draft":
        head.append("draft: true")
    for key in sorted(set(meta) - {"title", "date", "tags", "category", "summary", "slug"}):
        if key == "status":
            continue
        value, at = meta[key]
        if key in ("author", "authors"):
            body = f"*{value}*\n\n{body}" if value else body  # no author key: kept as text
            out.notes.append((name, f"{key.title()}: kept as a line at the top of the post"))
        elif key not in _KNOWN or value:
            out.notes.append((name, f"metadata '{key}: {value}' (line {at}) has no equivalent"))
    body, links = _PELICAN_LINK.subn("../", body)
    if links:
        out.notes.append(
            (name, f"{links} Pelican link(s) ({{static}}, {{filename}}) made relative")
        )
    rel = f"blog/{path.stem}.md"
    out.files[rel] = ("\n".join(head) + "\n---\n" + body.rstrip() + "\n").encode("utf-8")
    out.posts.append((title, rel))


# -- reveal decks ---------------------------------------------------------------------------


def _slides_div(path: Path) -> Element | None:
    if path.suffix != ".html":
        return None
    try:
        root, _ = parse_html(path.read_text(encoding="utf-8-sig", errors="replace"))
    except Exception:  # noqa: BLE001 (any HTML we cannot read is copied as is, not lost)
        return None
    for el in root.walk():
        if isinstance(el, Element) and el.tag == "div" and "slides" in el.classes():
            return el
    return None


def _sections(el: Element) -> list[Element]:
    return [c for c in el.children if isinstance(c, Element) and c.tag == "section"]


def _deck(path: Path, out: Imported) -> None:
    name = f"reveal/{path.name}"
    if path.suffix == ".md":  # reveal's external Markdown: already --- / -- / Note:
        text = path.read_text(encoding="utf-8-sig", errors="replace")
        rel = f"slides/{path.stem}.md"
        out.files[rel] = b"---\nslides: true\n---\n" + text.encode("utf-8")
        out.decks.append((path.stem, rel))
        return
    div = _slides_div(path)
    if div is None or not _sections(div):
        out.copies[name] = path
        out.notes.append((name, 'no reveal <div class="slides"> sections: copied as it is'))
        return
    notes: list[str] = []
    hooks = Hooks(
        url=lambda url, el, attr: url,
        data_image=lambda uri, el: None,
        warn=lambda m, n: notes.append(f"{m} (line {n})"),
    )
    parts = []
    for i, top in enumerate(_sections(div)):
        inner = _sections(top)
        if i:
            parts.append("---")
        for j, sub in enumerate(inner or [top]):
            if j:
                parts.append("--")
            parts.append(_slide(sub, hooks))
    title = next(
        (
            el.text().strip()
            for el in div.walk()
            if isinstance(el, Element) and el.tag in ("h1", "h2")
        ),
        path.stem,
    )
    rel = f"slides/{path.stem}.md"
    text = (
        f"---\ntitle: {mdtext.yaml_string(title)}\nslides: true\n---\n" + "\n\n".join(parts) + "\n"
    )
    out.files[rel] = text.encode("utf-8")
    out.decks.append((title, rel))
    out.notes.extend((name, n) for n in dict.fromkeys(notes))


def _slide(section: Element, hooks: Hooks) -> str:
    """One reveal section -> Markdown; its ``<aside class="notes">`` -> ``Note:``."""
    if "data-markdown" in section.attrs:
        template = next(
            (
                c
                for c in section.walk()
                if isinstance(c, Element) and c.tag in ("textarea", "script")
            ),
            None,
        )
        source = template.text() if template is not None else section.text()
        return textwrap.dedent(source).strip("\n")
    notes = [
        c
        for c in section.children
        if isinstance(c, Element) and c.tag == "aside" and "notes" in c.classes()
    ]
    blocks: list[str] = []
    run: list = []
    for child in section.children:
        if any(child is n for n in notes):
            continue
        level = _HEADING.match(child.tag) if isinstance(child, Element) else None
        if level:  # the page converter leaves headings to cmsimde's page split
            blocks.append(Converter(hooks).convert(run))
            blocks.append("#" * int(level.group(1)) + " " + " ".join(child.text().split()))
            run = []
        else:
            run.append(child)
    blocks.append(Converter(hooks).convert(run))
    text = "\n\n".join(b for b in blocks if b.strip())
    for aside in notes:
        said = Converter(hooks).convert(aside.children) or aside.text().strip()
        text += f"\n\nNote: {said}"
    return text.strip() or "&nbsp;"
