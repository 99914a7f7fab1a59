"""cmsimde's one HTML file cut into pages, as cmsimde cuts it: at every H1, H2 and H3.

A heading nests under the nearest earlier heading of a smaller level (cmsimde's menu); a
heading inside a container (``<div><h2>``) splits the container, as cmsimde's raw cut does.
Each page gets a numbered file name and a ``weight`` so sitegen's depth-first walk gives back
cmsimde's order. :mod:`sitegen.importers.cmsimde` converts and writes the pages.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import PurePosixPath

from sitegen.importers.htmltree import Element, Node, ParseIssue, Text
from sitegen.slugs import slugify

PAGE_HEADINGS = ("h1", "h2", "h3")
_RESERVED_STEMS = {"index", "readme", "_index"}  # sitegen reads these as a folder's own page


@dataclass
class Page:
    """One heading of content.htm and the nodes up to the next one."""

    title: str
    level: int
    line: int
    nodes: list[Node]
    children: list[Page] = field(default_factory=list)
    rel: PurePosixPath = PurePosixPath("index.md")
    weight: int = 0


def _is_page_heading(node: Node) -> bool:
    return isinstance(node, Element) and node.tag in PAGE_HEADINGS and bool(node.text().strip())


def _contains_heading(el: Element) -> bool:
    return any(_is_page_heading(n) for n in el.walk())


def _flatten(nodes: list[Node], lifted: list[Element]) -> list[Node]:
    """Bring headings nested in containers (``<div><h2>``) to the top, splitting the container.

    cmsimde cuts the raw text at each heading, which splits such a container too; we split it
    cleanly (one copy of the container before the heading, one after).
    """
    out: list[Node] = []
    for node in nodes:
        if isinstance(node, Element) and not _is_page_heading(node) and _contains_heading(node):
            lifted.append(node)
            buffer: list[Node] = []
            for part in _flatten(node.children, lifted):
                if _is_page_heading(part):
                    if buffer:
                        out.append(node.clone(buffer))
                        buffer = []
                    out.append(part)
                else:
                    buffer.append(part)
            if buffer:
                out.append(node.clone(buffer))
        else:
            out.append(node)
    return out


def split_pages(root: Element, notes: list[ParseIssue]) -> tuple[list[Node], list[Page]]:
    lifted: list[Element] = []
    nodes = _flatten(root.children, lifted)
    for el in lifted:
        notes.append(ParseIssue(el.line, f"<{el.tag}> holds page headings: split at them"))
    preamble: list[Node] = []
    pages: list[Page] = []
    for node in nodes:
        if _is_page_heading(node):
            assert isinstance(node, Element)
            pages.append(Page(node.text().strip(), int(node.tag[1]), node.line, []))
        elif isinstance(node, Element) and node.tag in PAGE_HEADINGS:
            notes.append(
                ParseIssue(node.line, f"empty <{node.tag}> is not a page (cmsimde drops it)")
            )
            (pages[-1].nodes if pages else preamble).append(node)
        else:
            (pages[-1].nodes if pages else preamble).append(node)
    return preamble, pages


def heading_markup(root: Element) -> dict[int, list[str]]:
    """Elements inside page headings (links, images...): only their text survives as title."""
    found: dict[int, list[str]] = {}
    for el in root.walk():
        if _is_page_heading(el):
            assert isinstance(el, Element)
            tags = sorted({n.tag for n in el.walk() if isinstance(n, Element)})
            if tags:
                found[el.line] = tags
    return found


def nest(pages: list[Page]) -> list[Page]:
    """Each heading goes under the nearest earlier heading of a smaller level (as cmsimde's
    menu)."""
    top: list[Page] = []
    stack: list[Page] = []
    for page in pages:
        while stack and stack[-1].level >= page.level:
            stack.pop()
        (stack[-1].children if stack else top).append(page)
        stack.append(page)
    return top


def assign_paths(pages: list[Page], folder: PurePosixPath) -> None:
    width = max(2, len(str(len(pages))))
    for number, page in enumerate(pages, 1):
        stem = slugify(page.title, "page")
        if stem in _RESERVED_STEMS:
            stem += "-page"
        name = f"{number:0{width}d}-{stem}"
        page.weight = number
        if page.children:
            page.rel = folder / name / "index.md"
            assign_paths(page.children, folder / name)
        else:
            page.rel = folder / f"{name}.md"


def walk_pages(pages: list[Page]) -> Iterator[Page]:
    for page in pages:
        yield page
        yield from walk_pages(page.children)


def visible(nodes: list[Node]) -> bool:
    """Whether the text before the first heading shows anything (else no front page)."""
    for node in nodes:
        if isinstance(node, Text) and node.data.replace("\xa0", " ").strip():
            return True
        if isinstance(node, Element) and node.tag not in (
            "script",
            "style",
            "br",
            "p",
            "div",
            "span",
        ):
            return True
        if isinstance(node, Element) and visible(node.children):
            return True
    return False
