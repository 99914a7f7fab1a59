"""A small, forgiving HTML tree for converting cmsimde content.

cmsimde pages are TinyMCE output plus whatever students pasted (Google Translate markup,
rendered SyntaxHighlighter tables, hand-typed tags inside code). We need a tree, source line
numbers for the report, and a record of what was broken, so we build on the stdlib
``html.parser`` (which never fails) and add the few HTML recovery rules that matter here:
void elements, ``<p>``/``<li>``/table cells closing implicitly, stray end tags ignored.
"""

from __future__ import annotations

import html
from dataclasses import dataclass, field
from html.parser import HTMLParser

VOID = frozenset("area base br col embed hr img input link meta param source track wbr".split())
#: Elements whose end tag HTML lets you leave out: not reported when closed implicitly.
OPTIONAL_END = frozenset(
    "p li dt dd tr td th thead tbody tfoot option optgroup colgroup caption rb rt rp".split()
)
#: Start tags that close an open <p> (HTML "close a p element").
CLOSES_P = frozenset(
    """address article aside blockquote center details dialog dir div dl fieldset figcaption
    figure footer form h1 h2 h3 h4 h5 h6 header hgroup hr main menu nav ol p pre section
    table ul""".split()
)
_P_SCOPE_STOP = frozenset("table td th caption button object template marquee applet pre".split())
#: tag -> (tags it closes when opened, tags that stop the search)
_IMPLIED = {
    "li": ({"li"}, {"ul", "ol", "menu", "table"}),
    "dt": ({"dt", "dd"}, {"dl", "table"}),
    "dd": ({"dt", "dd"}, {"dl", "table"}),
    "tr": ({"tr", "td", "th"}, {"table", "thead", "tbody", "tfoot"}),
    "td": ({"td", "th"}, {"tr", "table"}),
    "th": ({"td", "th"}, {"tr", "table"}),
    "thead": ({"thead", "tbody", "tfoot", "tr", "td", "th"}, {"table"}),
    "tbody": ({"thead", "tbody", "tfoot", "tr", "td", "th"}, {"table"}),
    "tfoot": ({"thead", "tbody", "tfoot", "tr", "td", "th"}, {"table"}),
    "option": ({"option"}, {"select", "datalist", "optgroup"}),
}


@dataclass
class Text:
    data: str
    line: int


@dataclass
class Comment:
    data: str
    line: int


@dataclass
class Element:
    tag: str
    attrs: dict[str, str]
    children: list[Node] = field(default_factory=list)
    line: int = 0
    raw_start: str = ""  # the start tag as written, to reproduce typed tags inside code

    def text(self) -> str:
        """All descendant text, as ``element.textContent`` would give it."""
        parts: list[str] = []
        for node in self.walk():
            if isinstance(node, Text):
                parts.append(node.data)
        return "".join(parts)

    def walk(self):
        """Yield every descendant node, depth-first, in document order."""
        for child in self.children:
            yield child
            if isinstance(child, Element):
                yield from child.walk()

    def find_all(self, tag: str) -> list[Element]:
        return [n for n in self.walk() if isinstance(n, Element) and n.tag == tag]

    def classes(self) -> list[str]:
        return self.attrs.get("class", "").split()

    def clone(self, children: list[Node]) -> Element:
        return Element(self.tag, dict(self.attrs), children, self.line, self.raw_start)


Node = Element | Text | Comment


@dataclass
class ParseIssue:
    """Something broken in the markup, reported to the user with its line."""

    line: int
    message: str


class _TreeBuilder(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.root = Element("#root", {})
        self.stack: list[Element] = [self.root]
        self.issues: list[ParseIssue] = []

    # -- helpers -------------------------------------------------------------------------
    def _pop_to(self, index: int, why: str) -> None:
        """Close stack[index:] ; report elements whose end tag may not be left out."""
        for el in reversed(self.stack[index:]):
            if el.tag not in OPTIONAL_END:
                self.issues.append(ParseIssue(el.line, f"unclosed <{el.tag}> ({why})"))
        del self.stack[index:]

    def _find_open(self, tags: set[str] | frozenset[str], stop: set[str] | frozenset[str]) -> int:
        for i in range(len(self.stack) - 1, 0, -1):
            tag = self.stack[i].tag
            if tag in tags:
                return i
            if tag in stop:
                return -1
        return -1

    def _append(self, node: Node) -> None:
        self.stack[-1].children.append(node)

    # -- parser callbacks ----------------------------------------------------------------
    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self._start(tag, attrs, self_closing=False)

    def handle_startendtag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self._start(tag, attrs, self_closing=True)

    def _start(self, tag: str, attrs: list[tuple[str, str | None]], self_closing: bool) -> None:
        line = self.getpos()[0]
        if tag in CLOSES_P:
            at = self._find_open({"p"}, _P_SCOPE_STOP)
            if at > 0:
                self._pop_to(at, f"closed by <{tag}> at line {line}")
        implied = _IMPLIED.get(tag)
        if implied:
            at = self._find_open(implied[0], implied[1] | {"pre"})
            if at > 0:
                self._pop_to(at, f"closed by <{tag}> at line {line}")
        values: dict[str, str] = {}
        for name, value in attrs:
            values.setdefault(name, value or "")
        el = Element(tag, values, [], line, self.get_starttag_text() or f"<{tag}>")
        self._append(el)
        if tag not in VOID and not self_closing:
            self.stack.append(el)

    def handle_endtag(self, tag: str) -> None:
        line = self.getpos()[0]
        if tag == "br":  # browsers read </br> as <br>
            self._append(Element("br", {}, [], line, "</br>"))
            return
        if tag in VOID:  # </img>, </source>: meaningless, browsers ignore them
            return
        for i in range(len(self.stack) - 1, 0, -1):
            if self.stack[i].tag == tag:
                self._pop_to(i + 1, f"closed by </{tag}> at line {line}")
                self.stack.pop()
                return
        self.issues.append(ParseIssue(line, f"stray </{tag}> ignored"))

    def handle_data(self, data: str) -> None:
        self._append(Text(data, self.getpos()[0]))

    def handle_comment(self, data: str) -> None:
        self._append(Comment(data, self.getpos()[0]))

    def close(self) -> None:
        super().close()
        self._pop_to(1, "at end of file")


def parse_html(source: str) -> tuple[Element, list[ParseIssue]]:
    """Parse ``source`` into a tree under a ``#root`` element; never raises."""
    builder = _TreeBuilder()
    builder.feed(source)
    builder.close()
    return builder.root, builder.issues


# -- serialising back to HTML (for what Markdown cannot express) ------------------------------

RAW_TEXT = frozenset({"script", "style"})


def to_html(node: Node, rewrite=None, replace=None) -> str:
    """Serialise ``node``; ``rewrite(el, attr, value)`` may change URL attributes, and
    ``replace(el)`` may give the HTML of a whole element instead (None: serialise it).

    The ``markdown`` attribute is dropped: with ``md_in_html`` it would turn raw HTML back
    into Markdown and change what the page shows.
    """
    if isinstance(node, Text):
        return html.escape(node.data, quote=False)
    if isinstance(node, Comment):
        return f"<!--{node.data}-->"
    if replace is not None:
        instead = replace(node)
        if instead is not None:
            return instead
    attrs = []
    for name, value in node.attrs.items():
        if name == "markdown":
            continue
        if rewrite is not None:
            value = rewrite(node, name, value)
            if value is None:
                continue
        attrs.append(f' {name}="{html.escape(value, quote=True)}"')
    start = f"<{node.tag}{''.join(attrs)}>"
    if node.tag in VOID:
        return start
    if node.tag in RAW_TEXT:
        inner = "".join(c.data for c in node.children if isinstance(c, Text))
    else:
        inner = "".join(to_html(c, rewrite, replace) for c in node.children)
    return f"{start}{inner}</{node.tag}>"
