"""Inline HTML -> Markdown: text, emphasis, code spans, links, images, styled spans.

The half of the converter that works inside one paragraph (or heading, table cell, list
item). Kept apart from the block half in :mod:`sitegen.importers.html_to_markdown`, which
builds on :class:`InlineConverter`. Tag tables live here because both halves use them.
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass

from located.diagnostics import quoted
from sitegen.importers import mdtext
from sitegen.importers.htmltree import Element, Node, Text, to_html
from sitegen.links import external_problem

HEADINGS = {"h1", "h2", "h3", "h4", "h5", "h6"}
#: Dropped everywhere except inside code, with a warning.
DROP = {"script", "style", "link", "meta", "head", "title", "base"}
#: Kept verbatim as HTML: Markdown has no equivalent.
RAW = {
    "iframe",
    "video",
    "audio",
    "object",
    "embed",
    "canvas",
    "svg",
    "math",
    "map",
    "button",
    "input",
    "select",
    "textarea",
    "form",
    "picture",
    "dl",
    "details",
    "fieldset",
    "noscript",
    "progress",
    "meter",
    "output",
}
#: Blocks whose children are simply rendered in their place.
TRANSPARENT = {
    "div",
    "section",
    "article",
    "aside",
    "header",
    "footer",
    "main",
    "nav",
    "center",
    "figure",
    "figcaption",
    "html",
    "body",
    "address",
    "hgroup",
    "li",
    "tr",
    "td",
    "th",
    "thead",
    "tbody",
    "tfoot",
    "caption",
    "menu",
    "dir",
}
BLOCKS = (
    HEADINGS
    | TRANSPARENT
    | {"p", "pre", "ul", "ol", "table", "blockquote", "hr"}
    | {"dl", "details", "fieldset", "form", "noscript"}
)
#: Inline tags kept as HTML around Markdown content (none is "block-level" to Markdown).
WRAP = {
    "u": "u",
    "ins": "ins",
    "mark": "mark",
    "sub": "sub",
    "sup": "sup",
    "small": "small",
    "big": "big",
    "s": "s",
    "strike": "s",
    "del": "del",
    "abbr": "abbr",
    "q": "q",
}
EMPHASIS = {"strong": "**", "b": "**", "em": "*", "i": "*", "cite": "*", "var": "*", "dfn": "*"}
CODE = {"code", "kbd", "samp", "tt"}
SILENT_UNWRAP = {
    "span",
    "font",
    "label",
    "bdi",
    "bdo",
    "data",
    "time",
    "nobr",
    "legend",
    "optgroup",
    "option",
    "summary",
    "rb",
    "rt",
    "rp",
    "ruby",
    "colgroup",
    "col",
    "area",
    "source",
    "track",
    "param",
    "wbr",
    "center",
}
KEEP_SPAN_STYLE = {
    "color",
    "background-color",
    "background",
    "font-weight",
    "font-style",
    "text-decoration",
    "font-size",
}


@dataclass
class Hooks:
    """What the converter asks its caller: URL rewriting, data: images, warnings."""

    url: Callable[[str, Element, str], str]  # (url, element, attribute) -> url
    data_image: Callable[[str, Element], str | None]  # data: URI -> new src, or None
    warn: Callable[[str, int], None]  # (message, source line)
    # an element's whole HTML instead of its own (a YouTube iframe's poster), or None
    replace: Callable[[Element], str | None] = lambda el: None


def _style(value: str) -> list[tuple[str, str]]:
    out = []
    for decl in value.split(";"):
        prop, _, val = decl.partition(":")
        if prop.strip() and val.strip():
            out.append((prop.strip().lower(), val.strip()))
    return out


def has_block(el: Element) -> bool:
    """Does ``el`` hold block-level content (so it cannot be rendered inline)?"""
    return any(isinstance(n, Element) and n.tag in BLOCKS for n in el.walk())


def _kind(node: Node) -> str | None:
    if isinstance(node, Element):
        return "code" if node.tag in CODE else EMPHASIS.get(node.tag)
    return None


def _merge_adjacent(nodes: list[Node]) -> list[Node]:
    """``<b>a</b><b>b</b>`` -> one ``<b>``: ``**a****b**`` (or two touching code spans) would
    not parse as two."""
    out: list[Node] = []
    for node in nodes:
        prev = out[-1] if out else None
        kind = _kind(node)
        if kind and isinstance(prev, Element) and isinstance(node, Element) and _kind(prev) == kind:
            out[-1] = prev.clone(prev.children + node.children)
        else:
            out.append(node)
    return out


class InlineConverter:
    """Renders inline content; counts the layout styles it drops for the page summary."""

    def __init__(self, hooks: Hooks) -> None:
        self.hooks = hooks
        self.dropped_styles: Counter[str] = Counter()
        self._emphasis: Counter[str] = Counter()
        self._in_table = False

    def _count_styles(self, el: Element) -> None:
        for prop, _ in _style(el.attrs.get("style", "")):
            self.dropped_styles[prop] += 1
        if "align" in el.attrs and el.tag not in ("td", "th"):
            self.dropped_styles["align"] += 1

    def raw(self, el: Element) -> str:
        """``el`` serialised as HTML, its URLs rewritten like Markdown ones."""
        html = to_html(el, self._rewrite_attr, self.hooks.replace).strip()
        if "<pre" not in html and "<textarea" not in html:
            html = re.sub(r"\n[ \t]*(?=\n)", "", html)  # a blank line would end the HTML block
        return html

    def _rewrite_attr(self, el: Element, name: str, value: str) -> str | None:
        if name in ("src", "href", "poster") or (name == "data" and el.tag == "object"):
            value = value.strip()
            if value.startswith("data:") and el.tag == "img":
                return self.hooks.data_image(value, el)
            if value and not value.lower().startswith(("data:", "javascript:")):
                return self.hooks.url(value, el, name)
        return value

    # -- inline -------------------------------------------------------------------------
    def inline(self, nodes: list[Node], single_line: bool = False) -> str:
        parts: list[str] = []
        for node in _merge_adjacent(nodes):
            if isinstance(node, Text):
                text = mdtext.escape_text(mdtext.collapse_ws(node.data))
                parts.append(text.replace("|", "\\|") if self._in_table else text)
            elif isinstance(node, Element):
                parts.append(self.inline_element(node, single_line))
        return "".join(parts)

    def inline_element(self, el: Element, single_line: bool) -> str:
        tag = el.tag
        if tag == "br":
            return "<br />" if single_line else "<br />\n"
        if tag in EMPHASIS:
            return self._wrap(el, EMPHASIS[tag], single_line)
        if tag in CODE:
            return mdtext.code_span(el.text())
        if tag == "a":
            return self.link(el, single_line)
        if tag == "img":
            return self.image(el)
        if tag == "span" or tag == "font":
            return self._span(el, single_line)
        if tag in WRAP:
            inner = self.inline(el.children, single_line)
            return f"<{WRAP[tag]}>{inner}</{WRAP[tag]}>" if inner.strip() else inner
        if tag in RAW:
            html = self.raw(el)
            return re.sub(r"\s*\n\s*", " ", html) if tag not in ("textarea",) else html
        if tag == "pre" or tag in BLOCKS:
            inner = self.inline(el.children, single_line)
            sep = "<br />" if single_line else "<br />\n"
            return f"{sep}{inner.strip()}{sep}" if inner.strip() else ""
        if tag not in SILENT_UNWRAP:
            self.hooks.warn(f"unknown element <{tag}> unwrapped, its text kept", el.line)
        return self.inline(el.children, single_line)

    def _wrap(self, el: Element, marker: str, single_line: bool) -> str:
        self._count_styles(el)
        if self._emphasis[marker]:
            return self.inline(el.children, single_line)
        self._emphasis[marker] += 1
        try:
            inner = self.inline(el.children, single_line)
        finally:
            self._emphasis[marker] -= 1
        core = inner.strip(" \n")
        if not core or not re.sub(r"<br />|&nbsp;|\s", "", core):
            return inner
        lead = inner[: len(inner) - len(inner.lstrip(" \n"))]
        trail = inner[len(inner.rstrip(" \n")) :]
        return f"{lead}{marker}{core}{marker}{trail}"

    def _span(self, el: Element, single_line: bool) -> str:
        decls = _style(el.attrs.get("style", ""))
        if el.tag == "font":
            if el.attrs.get("color"):
                decls.append(("color", el.attrs["color"]))
            if el.attrs.get("size"):
                self.dropped_styles["font size"] += 1
        keep = [(p, v) for p, v in decls if p in KEEP_SPAN_STYLE]
        for p, _ in decls:
            if p not in KEEP_SPAN_STYLE:
                self.dropped_styles[p] += 1
        inner = self.inline(el.children, single_line)
        if not keep or not inner.strip():
            return inner
        style = "; ".join(f"{p}: {v}" for p, v in keep) + ";"
        start = to_html(Element("span", {"style": style}))[: -len("</span>")]
        return f"{start}{inner}</span>"

    def link(self, el: Element, single_line: bool) -> str:
        href = el.attrs.get("href", "").strip()
        inner = self.inline(el.children, single_line=True)
        anchor = el.attrs.get("id") or el.attrs.get("name")
        prefix = to_html(Element("a", {"id": anchor})) if anchor else ""
        if not href:
            return prefix + inner
        if href.lower().startswith("javascript:"):
            self.hooks.warn(f"javascript: link not carried over ({href[:40]})", el.line)
            return prefix + inner
        problem = external_problem(href)
        if problem and problem.startswith("malformed"):
            # a browser cannot follow it either (`http://[組長IP]:23020`, a placeholder): the
            # text stays, the URL is kept in a comment beside it, and the report says so
            self.hooks.warn(
                f"link {quoted(href)}: {problem.split(';')[0]}; its text is kept, "
                "not as a link (the URL is in a comment beside it)",
                el.line,
            )
            kept = href.replace("--", "- -").replace(">", "&gt;")
            return f"{prefix}{inner}<!-- link URL that does not parse: {kept} -->"
        url = self.hooks.url(href, el, "href")
        if self._in_table:
            url = url.replace("|", "%7C")
        plain = mdtext.collapse_ws(el.text()).strip()
        if (
            plain == href == url
            and len(el.children) == 1
            and isinstance(el.children[0], Text)
            and re.fullmatch(r"https?://[^\s<>|]+", href)
            and not el.attrs.get("title")
        ):
            return f"{prefix}<{href}>"
        core = inner.strip(" ")
        lead = " " if inner.startswith(" ") else ""
        trail = " " if inner.endswith(" ") else ""
        title = mdtext.link_title(mdtext.collapse_ws(el.attrs.get("title", "")).strip())
        return f"{prefix}{lead}[{core}]({mdtext.link_destination(url)}{title}){trail}"

    def image(self, el: Element) -> str:
        src = el.attrs.get("src", "").strip()
        if not src:
            self.hooks.warn("<img> without src dropped", el.line)
            return ""
        new = (
            self.hooks.data_image(src, el)
            if src.startswith("data:")
            else self.hooks.url(src, el, "src")
        )
        if new is None:
            return ""
        alt = el.attrs.get("alt", "")
        title = el.attrs.get("title", "")
        extra = {
            k: el.attrs[k] for k in ("width", "height", "style") if el.attrs.get(k, "").strip()
        }
        if extra:
            attrs = {"src": new, "alt": alt, **({"title": title} if title else {}), **extra}
            return to_html(Element("img", attrs))
        return (
            f"![{mdtext.escape_alt(alt)}]({mdtext.link_destination(new)}{mdtext.link_title(title)})"
        )
