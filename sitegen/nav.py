"""Source records -> navigation: the page tree, URLs, document order, menus.

Pure functions over plain data. A folder is a section whose own page is its ``index.md``
(or a generated list of its children); children are ordered by weight, numeric prefix, then
natural name; document order (previous/next) is the depth-first walk, as in cmsimde where
each heading's page is followed by its sub-headings' pages.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import PurePosixPath
from typing import Any

from sitegen.page_text import DeferredText, first_heading
from sitegen.slugs import slugify, unique

RESERVED_ROOT = {"index", "404", "search", "sitemap", "assets", "clips", "roster"}
_DIGITS = re.compile(r"(\d+)")


@dataclass
class PageInput(DeferredText):
    """What navigation needs to know of a page, whatever produced it. A content page taken
    from the last scan reads its ``text`` only when something uses it
    (sitegen.source_records)."""

    rel: PurePosixPath  # content-relative source path (real or virtual)
    meta: dict[str, Any]
    text: str  # Markdown, or "" for generated pages
    is_index: bool
    prefix: int | None
    stem: str
    body_html: str | None = None  # set for generated pages, already escaped
    body_line: int = 1
    digest: str = ""
    toc: list[dict] | None = None  # generated pages may give their own table of contents
    #: known without the text for a content page (SourcePage.text_key, .heading); never
    #: copied by dataclasses.replace, so a page whose text an integration changed has none
    text_key: str = field(default="", init=False, repr=False, compare=False)
    heading: tuple | None = field(default=None, init=False, repr=False, compare=False)

    def first_heading(self) -> tuple[str | None, int, bool]:
        return self.heading if self.heading is not None else first_heading(self.text)


@dataclass(eq=False)
class Node:
    """A page in the site tree. Sections are nodes with children."""

    title: str
    url: str  # output path from the site root, e.g. stage-1/w1/index.html
    source: PageInput | None  # None for a generated section index
    rel_dir: PurePosixPath  # the content folder this node lives in (or is, for sections)
    is_section: bool
    sort_key: tuple = ()
    parent: Node | None = None
    children: list[Node] = field(default_factory=list)
    index: int = 0  # position in document order
    strip_first_heading: bool = False

    @property
    def depth(self) -> int:
        return self.url.count("/")

    def ancestors(self) -> list[Node]:
        out, node = [], self.parent
        while node is not None:
            out.append(node)
            node = node.parent
        return out[::-1]


@dataclass
class Site:
    """The page tree with its document order and lookups by source path and folder."""

    root: Node
    order: list[Node]  # document order, root first
    by_source: dict[PurePosixPath, Node]  # content-relative .md path -> node
    by_dir: dict[PurePosixPath, Node]  # content folder -> section node


def natural_key(text: str) -> tuple:
    """Sort 'w2' before 'w10'."""
    return tuple(
        (0, int(t), "") if t.isdigit() else (1, 0, t.lower()) for t in _DIGITS.split(text) if t
    )


def _pretty(stem: str) -> str:
    return stem.replace("_", " ").replace("-", " ").strip() or stem


def _title_for(page: PageInput) -> tuple[str, bool]:
    if "title" in page.meta:
        title, level, first = page.first_heading()
        return page.meta["title"], bool(first and level == 1 and title == page.meta["title"])
    title, level, first = page.first_heading()
    if title:
        return title, first and level == 1
    return _pretty(page.stem), False


def _key(meta: dict, prefix: int | None, name: str) -> tuple:
    weight = meta.get("weight")
    big = 10**9
    return (
        weight if weight is not None else big,
        prefix if prefix is not None else big,
        natural_key(name),
    )


def build_site(pages: list[PageInput], home_title: str = "Home") -> Site:
    """Arrange pages into a tree with URLs and document order."""
    # Group pages per folder; every ancestor of a page's folder is a section.
    top = PurePosixPath(".")
    dirs: dict[PurePosixPath, list[PageInput]] = {top: []}
    parents: dict[PurePosixPath, PurePosixPath] = {}  # pathlib makes a new object per .parent
    # pages grouped by their folder's name first: hashing a path object costs more than
    # hashing its string, and there are as many pages as lookups
    named: dict[str, list[PageInput]] = {}
    for page in sorted(pages, key=lambda p: str(p.rel)):
        folder = str(page.rel).rpartition("/")[0]
        group = named.get(folder)
        if group is None:
            group = named[folder] = []
        group.append(page)
    for group in named.values():
        d = group[0].rel.parent
        if d in dirs:  # an ancestor of a folder seen before
            dirs[d].extend(group)
            continue
        dirs[d] = group
        while d != top:
            up = parents[d] = d.parent
            if up in dirs:
                break
            dirs[up] = []
            d = up
    subdirs: dict[PurePosixPath, list[PurePosixPath]] = {d: [] for d in dirs}
    for d in dirs:
        if d != top:
            subdirs[parents[d]].append(d)

    by_source: dict[PurePosixPath, Node] = {}
    by_dir: dict[PurePosixPath, Node] = {}

    def make_section(d: PurePosixPath, url_dir: str) -> Node:
        entries = dirs[d]
        index = next((p for p in entries if p.is_index), None)
        prefix, stem = _split(d.name) if d.name else (None, "")
        if index is not None:
            title, strip = _title_for(index)
            if "title" not in index.meta and not index.first_heading()[0]:
                title, strip = (_pretty(stem) if d.name else home_title), False
        else:
            title, strip = (_pretty(stem) if d.name else home_title), False
        url = f"{url_dir}/index.html" if url_dir else "index.html"
        meta = index.meta if index else {}
        node = Node(title, url, index, d, True, _key(meta, prefix, stem), strip_first_heading=strip)
        by_dir[d] = node
        if index is not None:
            by_source[index.rel] = node
        children: list[Node] = []
        for page in entries:
            if page is index:
                continue
            t, s = _title_for(page)
            children.append(
                Node(
                    t,
                    "",
                    page,
                    d,
                    False,
                    _key(page.meta, page.prefix, page.stem),
                    strip_first_heading=s,
                )
            )
        for sub in subdirs[d]:
            sub_index = next((p for p in dirs[sub] if p.is_index), None)
            sub_prefix, sub_stem = _split(sub.name)
            key = _key(sub_index.meta if sub_index else {}, sub_prefix, sub_stem)
            children.append(Node("", "", None, sub, True, key))  # placeholder, filled below
        children.sort(key=lambda n: n.sort_key)
        taken = set(RESERVED_ROOT) if not url_dir else {"index"}
        final: list[Node] = []
        for child in children:
            if child.is_section:
                sub_index = next((p for p in dirs[child.rel_dir] if p.is_index), None)
                explicit = sub_index.meta.get("slug") if sub_index else None
                _, sub_stem = _split(child.rel_dir.name)
                slug = unique(slugify(explicit or sub_stem, "section"), taken)
                real = make_section(child.rel_dir, f"{url_dir}/{slug}" if url_dir else slug)
                real.sort_key = child.sort_key
                child = real
            else:
                assert child.source is not None
                explicit = child.source.meta.get("slug")
                slug = unique(slugify(explicit or child.title, "page"), taken)
                child.url = f"{url_dir}/{slug}.html" if url_dir else f"{slug}.html"
                by_source[child.source.rel] = child
            child.parent = node
            final.append(child)
        node.children = final
        return node

    root = make_section(top, "")
    order: list[Node] = []

    def walk(n: Node) -> None:
        n.index = len(order)
        order.append(n)
        for c in n.children:
            walk(c)

    walk(root)
    return Site(root, order, by_source, by_dir)


def _split(name: str) -> tuple[int | None, str]:
    from sitegen.content import split_name

    return split_name(name)


def menu_for(site: Site, node: Node, mark_current: bool = True) -> list[dict]:
    """The menu shown on ``node``: top level, plus the open branch down to the page.

    Listing every page on every page makes output grow as pages squared; a 1000-page site
    would write a 1000-item menu 1000 times. Only the current branch is expanded here; the
    Site Map page holds the full tree. With ``mark_current=False`` nothing is marked current:
    the menu every page of one folder shares (:func:`menu_owner`), rendered once per folder.
    """
    branch = set(id(a) for a in node.ancestors()) | {id(node)}
    current = node if mark_current else None

    def item(n: Node) -> dict:
        open_ = id(n) in branch
        kids = [item(c) for c in n.children] if (open_ and n.children) else []
        return {
            "title": n.title,
            "url": n.url,
            "current": n is current,
            "open": open_,
            "has_children": bool(n.children),
            "children": kids,
        }

    top = [
        {
            "title": site.root.title,
            "url": site.root.url,
            "current": current is site.root,
            "open": False,
            "has_children": False,
            "children": [],
        }
    ]
    return top + [item(c) for c in site.root.children]


def menu_owner(node: Node) -> Node | None:
    """The node whose unmarked menu ``node`` shows: its folder for a page, None for a section
    or the home page (whose menus open their own children, so they are not shared)."""
    if node.is_section or node.parent is None:
        return None
    return node.parent


def full_tree(site: Site) -> list[dict]:
    def item(n: Node) -> dict:
        return {"title": n.title, "url": n.url, "children": [item(c) for c in n.children]}

    return [{"title": site.root.title, "url": site.root.url, "children": []}] + [
        item(c) for c in site.root.children
    ]
