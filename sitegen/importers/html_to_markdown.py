"""cmsimde page HTML -> Markdown that shows the same text.

Rules, in order of preference: plain Markdown where it says the same thing (paragraphs,
emphasis, links, lists, simple tables, code); inline HTML for what matters but has no
Markdown form (highlight spans, sized images, underline); raw HTML blocks for what Markdown
cannot express at all (iframes, video, rowspan tables); and a warning, with its source line,
for whatever is dropped (scripts, layout styles, unknown elements). URL decisions belong to
the caller, through :class:`Hooks`.
"""

from __future__ import annotations

import re

from sitegen.importers import mdtext
from sitegen.importers.html_code import code_block, code_text, highlighter_code, pre_language
from sitegen.importers.html_inline import (
    BLOCKS,
    CODE,
    DROP,
    EMPHASIS,
    HEADINGS,
    RAW,
    SILENT_UNWRAP,
    TRANSPARENT,
    WRAP,
    Hooks,
    InlineConverter,
    has_block,
)
from sitegen.importers.htmltree import Comment, Element, Node, Text

_MD_BLOCKS = HEADINGS | {"p", "pre", "ul", "ol", "table", "blockquote"}
#: What a <pre> of pasted text may show that code text cannot: kept by keeping the <pre>.
_MEDIA = ("img", "iframe", "video", "audio", "object", "embed", "svg", "picture")

__all__ = ["Converter", "Hooks"]


class Converter(InlineConverter):
    """Converts one page; collects counts of what it dropped for a per-page summary."""

    def __init__(self, hooks: Hooks) -> None:
        super().__init__(hooks)
        self.comments = 0
        self._nested = 0

    # -- entry points -------------------------------------------------------------------
    def convert(self, nodes: list[Node]) -> str:
        body = "\n\n".join(b for b in self.blocks(self.prune(nodes)) if b.strip())
        self._summarise()
        return body

    def prune(self, nodes: list[Node]) -> list[Node]:
        """Drop scripts, styles and comments (not inside code), warning once for each."""
        out: list[Node] = []
        for node in nodes:
            if isinstance(node, Comment):
                self.comments += 1
            elif isinstance(node, Element) and node.tag in DROP:
                self._warn_dropped(node)
            elif isinstance(node, Element) and node.tag != "pre":
                out.append(node.clone(self.prune(node.children)))
            else:
                out.append(node)
        return out

    def _warn_dropped(self, el: Element) -> None:
        if el.tag == "script":
            kind = el.attrs.get("type", "").lower()
            what = "Brython (Python) script" if "python" in kind else "<script>"
            src = el.attrs.get("src")
            count = len(el.text().strip().splitlines())
            detail = f"src={src}" if src else f"{count} line{'' if count == 1 else 's'} inline"
            self.hooks.warn(f"{what} not carried over ({detail})", el.line)
        elif el.tag == "style":
            self.hooks.warn("<style> element not carried over", el.line)
        else:
            self.hooks.warn(f"<{el.tag}> element not carried over", el.line)

    def _summarise(self) -> None:
        if self.dropped_styles:
            parts = ", ".join(f"{k} ({v})" for k, v in sorted(self.dropped_styles.items()))
            self.hooks.warn(f"layout styles not carried over: {parts}", 0)
        if self.comments:
            self.hooks.warn(f"{self.comments} HTML comment(s) dropped", 0)

    # -- blocks -------------------------------------------------------------------------
    def blocks(self, nodes: list[Node]) -> list[str]:
        out: list[str] = []
        run: list[Node] = []

        def flush() -> None:
            if run:
                para = self.paragraph(run)
                if para:
                    out.append(para)
                run.clear()

        for node in nodes:
            if isinstance(node, Element) and (
                node.tag in BLOCKS or (node.tag not in RAW and has_block(node))
            ):
                flush()
                out.extend(b for b in self.block(node) if b.strip())
            else:
                run.append(node)
        flush()
        return out

    def block(self, el: Element) -> list[str]:
        tag = el.tag
        if tag == "p":
            self._count_styles(el)
            para = self.paragraph(el.children)
            return [para] if para else []
        if tag in HEADINGS:
            return self.heading(el)
        if tag == "pre":
            return [self.pre(el)]
        if tag in ("ul", "ol"):
            return [self.list_block(el)]
        if tag == "table":
            return [self.table(el)]
        if tag == "blockquote":
            return [self.quote(el)]
        if tag == "hr":
            return ["---"]
        if tag in RAW:
            return [self.raw(el)]
        if tag == "div" and "syntaxhighlighter" in el.classes():
            found = highlighter_code(el)
            if found is not None:
                self.hooks.warn(
                    "rendered SyntaxHighlighter table turned back into a code block "
                    "(line numbers dropped)",
                    el.line,
                )
                return [self._code(found[0], found[1], el.line)]
        if tag == "div" and self._raw_only(el):
            return [self.raw(el)]
        if tag not in TRANSPARENT and tag not in SILENT_UNWRAP:
            if tag == "a" and el.attrs.get("href"):
                self.hooks.warn(
                    f"link around block content not carried over ({el.attrs['href']})", el.line
                )
            elif tag in EMPHASIS or tag in WRAP or tag in CODE:
                self.hooks.warn(f"<{tag}> around block content: formatting dropped", el.line)
            else:
                self.hooks.warn(f"unknown element <{tag}> unwrapped, its content kept", el.line)
        self._count_styles(el)
        return self.blocks(el.children)

    def _raw_only(self, el: Element) -> bool:
        """A div of players and controls (Wink video) with no text: keep it whole."""
        has_raw = False
        for node in el.walk():
            if isinstance(node, Element):
                if node.tag in _MD_BLOCKS:
                    return False
                has_raw = has_raw or node.tag in RAW
            elif isinstance(node, Text) and node.data.strip():
                return False
        return has_raw

    def paragraph(self, nodes: list[Node]) -> str:
        text = self.inline(nodes).strip(" \n")
        text = re.sub(r"^(?:<br />\s*)+|(?:\s*<br />)+$", "", text)
        if not re.sub(r"<br />|&nbsp;|\s", "", text):
            return ""
        return mdtext.escape_line_starts(text)

    def heading(self, el: Element) -> list[str]:
        level = int(el.tag[1])
        text = self.inline(el.children, single_line=True).strip()
        if not re.sub(r"<br />|&nbsp;|\s", "", text):
            return []
        if level <= 3:  # only an empty H1-H3 is left in a page body: not a page in cmsimde
            return [mdtext.escape_line_starts(text)]
        return ["#" * level + " " + mdtext.escape_heading_end(text)]

    def quote(self, el: Element) -> str:
        self._nested += 1
        try:
            inner = "\n\n".join(self.blocks(el.children))
        finally:
            self._nested -= 1
        return "\n".join(("> " + line) if line else ">" for line in inner.split("\n"))

    def list_block(self, el: Element) -> str:
        ordered = el.tag == "ol"
        try:
            number = int(el.attrs.get("start", "1")) if ordered else 1
        except ValueError:
            number = 1
        items: list[list[str]] = []
        self._nested += 1
        try:
            for child in el.children:
                if isinstance(child, Text) and not child.data.strip():
                    continue
                if isinstance(child, Element) and child.tag in ("ul", "ol") and items:
                    items[-1].append(self.list_block(child))  # a list nested without its <li>
                    continue
                kids = (
                    child.children if isinstance(child, Element) and child.tag == "li" else [child]
                )
                blocks = self.blocks(kids)
                if blocks:
                    items.append(blocks)
        finally:
            self._nested -= 1
        # Python-Markdown reads an item after a multi-line one as its lazy continuation, so
        # such lists get blank lines between items (a "loose" list: same text, more spacing).
        loose = any(len(blocks) > 1 or "\n" in blocks[0] for blocks in items)
        lines: list[str] = []
        for blocks in items:
            if loose and lines:
                lines.append("")
            marker = f"{number}." if ordered else "-"
            number += 1
            body = "\n\n".join(blocks)
            if body.startswith("    "):  # an indented code block cannot share the marker line
                body = "&nbsp;\n" + body
            first, *rest = body.split("\n")
            lines.append(f"{marker} {first}")
            lines.extend(("    " + line) if line else "" for line in rest)
        return "\n".join(lines)

    # -- code ---------------------------------------------------------------------------
    def pre(self, el: Element) -> str:
        lang, known, brush = pre_language(el)
        if not known:
            self.hooks.warn(f"code language {lang!r} not recognised, kept as written", el.line)
        if not brush and (
            any("href" in a.attrs for a in el.find_all("a"))
            or any(el.find_all(tag) for tag in _MEDIA)
        ):
            # preformatted text with links or pictures (pasted from a translator): Markdown
            # code would lose them, so the <pre> is kept as HTML, its URLs rewritten
            return self.raw(el)
        typed: list[str] = []
        code = code_text(el.children, literal=brush, typed=typed)
        if typed:
            names = ", ".join(f"<{t}>" for t in sorted(set(typed)))
            self.hooks.warn(f"markup inside code kept as literal text: {names}", el.line)
        return self._code(code, lang, el.line)

    def _code(self, code: str, lang: str, line: int) -> str:
        if self._nested and lang and code.strip():
            self.hooks.warn(f"code block inside a list or quote: language {lang!r} not kept", line)
        return code_block(code, lang, nested=bool(self._nested))

    # -- tables -------------------------------------------------------------------------
    def table(self, el: Element) -> str:
        rows: list[Element] = []
        for child in el.children:
            if isinstance(child, Element) and child.tag in ("thead", "tbody", "tfoot"):
                rows.extend(c for c in child.children if isinstance(c, Element) and c.tag == "tr")
            elif isinstance(child, Element) and child.tag == "tr":
                rows.append(child)
            elif isinstance(child, Element) or (isinstance(child, Text) and child.data.strip()):
                return self.raw(el)  # caption, colgroup or stray content
        grid = [
            [c for c in tr.children if isinstance(c, Element) and c.tag in ("td", "th")]
            for tr in rows
        ]
        grid = [r for r in grid if r]
        if not grid:
            return ""
        for cell in (c for r in grid for c in r):
            spans = cell.attrs.get("rowspan", "1").strip() + cell.attrs.get("colspan", "1").strip()
            blocky = [
                n
                for n in cell.walk()
                if isinstance(n, Element) and n.tag in BLOCKS and n.tag != "p"
            ]
            if spans != "11" or blocky or len(cell.find_all("p")) > 1:
                return self.raw(el)
        width = max(len(r) for r in grid)
        self._in_table = True
        try:
            text = [
                [self.inline(self._cell_nodes(c), single_line=True).strip() for c in r]
                for r in grid
            ]
        finally:
            self._in_table = False
        text = [r + [""] * (width - len(r)) for r in text]
        out = ["| " + " | ".join(text[0]) + " |", "|" + " --- |" * width]
        out += ["| " + " | ".join(r) + " |" for r in text[1:]]
        for cell in (c for r in grid for c in r):
            self._count_styles(cell)
        return "\n".join(out)

    @staticmethod
    def _cell_nodes(cell: Element) -> list[Node]:
        return [
            n
            for c in cell.children
            for n in (c.children if isinstance(c, Element) and c.tag == "p" else [c])
        ]
