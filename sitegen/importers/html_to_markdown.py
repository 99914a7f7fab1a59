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
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass

from sitegen.importers import mdtext
from sitegen.importers.htmltree import VOID, Comment, Element, Node, Text, to_html

HEADINGS = {"h1", "h2", "h3", "h4", "h5", "h6"}
#: Dropped everywhere except inside code, with a warning.
DROP = {"script", "style", "link", "meta", "head", "title", "base"}
#: Kept verbatim as HTML: Markdown has no equivalent.
RAW = {"iframe", "video", "audio", "object", "embed", "canvas", "svg", "math", "map",
       "button", "input", "select", "textarea", "form", "picture", "dl", "details",
       "fieldset", "noscript", "progress", "meter", "output"}
#: Blocks whose children are simply rendered in their place.
TRANSPARENT = {"div", "section", "article", "aside", "header", "footer", "main", "nav",
               "center", "figure", "figcaption", "html", "body", "address", "hgroup", "li",
               "tr", "td", "th", "thead", "tbody", "tfoot", "caption", "menu", "dir"}
BLOCKS = HEADINGS | TRANSPARENT | {"p", "pre", "ul", "ol", "table", "blockquote", "hr"} | {
    "dl", "details", "fieldset", "form", "noscript"}
_MD_BLOCKS = HEADINGS | {"p", "pre", "ul", "ol", "table", "blockquote"}
#: Inline tags kept as HTML around Markdown content (none is "block-level" to Markdown).
WRAP = {"u": "u", "ins": "ins", "mark": "mark", "sub": "sub", "sup": "sup", "small": "small",
        "big": "big", "s": "s", "strike": "s", "del": "del", "abbr": "abbr", "q": "q"}
EMPHASIS = {"strong": "**", "b": "**", "em": "*", "i": "*", "cite": "*", "var": "*", "dfn": "*"}
CODE = {"code", "kbd", "samp", "tt"}
SILENT_UNWRAP = {"span", "font", "label", "bdi", "bdo", "data", "time", "nobr", "legend",
                 "optgroup", "option", "summary", "rb", "rt", "rp", "ruby", "colgroup", "col",
                 "area", "source", "track", "param", "wbr", "center"}
#: Formatting a code highlighter may leave inside <pre>; anything else there was typed code.
CODE_FORMATTING = {"span", "code", "b", "strong", "i", "em", "a", "font", "u", "mark", "sub",
                   "sup", "s", "small", "big"}
KEEP_SPAN_STYLE = {"color", "background-color", "background", "font-weight", "font-style",
                   "text-decoration", "font-size"}


@dataclass
class Hooks:
    """What the converter asks its caller: URL rewriting, data: images, warnings."""

    url: Callable[[str, Element, str], str]          # (url, element, attribute) -> url
    data_image: Callable[[str, Element], str | None]  # data: URI -> new src, or None
    warn: Callable[[str, int], None]                  # (message, source line)


def _style(value: str) -> list[tuple[str, str]]:
    out = []
    for decl in value.split(";"):
        prop, _, val = decl.partition(":")
        if prop.strip() and val.strip():
            out.append((prop.strip().lower(), val.strip()))
    return out


def _has_block(el: Element) -> bool:
    return any(isinstance(n, Element) and n.tag in BLOCKS for n in el.walk())


def _merge_adjacent(nodes: list[Node]) -> list[Node]:
    """``<b>a</b><b>b</b>`` -> one ``<b>``: ``**a****b**`` would not parse."""
    out: list[Node] = []
    for node in nodes:
        prev = out[-1] if out else None
        if (isinstance(node, Element) and isinstance(prev, Element) and node.tag in EMPHASIS
                and EMPHASIS.get(prev.tag) == EMPHASIS[node.tag]):
            out[-1] = prev.clone(prev.children + node.children)
        else:
            out.append(node)
    return out


class Converter:
    """Converts one page; collects counts of what it dropped for a per-page summary."""

    def __init__(self, hooks: Hooks) -> None:
        self.hooks = hooks
        self.dropped_styles: Counter[str] = Counter()
        self.comments = 0
        self._emphasis: Counter[str] = Counter()
        self._nested = 0
        self._in_table = False

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
            detail = f"src={src}" if src else f"{len(el.text().strip().splitlines())} lines inline"
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

    def _count_styles(self, el: Element) -> None:
        for prop, _ in _style(el.attrs.get("style", "")):
            self.dropped_styles[prop] += 1
        if "align" in el.attrs and el.tag not in ("td", "th"):
            self.dropped_styles["align"] += 1

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
                node.tag in BLOCKS or (node.tag not in RAW and _has_block(node))
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
            code = self.highlighter(el)
            if code is not None:
                return [code]
        if tag == "div" and self._raw_only(el):
            return [self.raw(el)]
        if tag not in TRANSPARENT and tag not in SILENT_UNWRAP:
            if tag == "a" and el.attrs.get("href"):
                self.hooks.warn(f"link around block content not carried over ({el.attrs['href']})", el.line)
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
                kids = child.children if isinstance(child, Element) and child.tag == "li" else [child]
                blocks = self.blocks(kids)
                if blocks:
                    items.append(blocks)
        finally:
            self._nested -= 1
        lines: list[str] = []
        for blocks in items:
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
        m = re.search(r"brush\s*:\s*([^;\s]+)", el.attrs.get("class", ""))
        spec = m.group(1) if m else ""
        lang, known = mdtext.brush_language(spec) if spec else ("", True)
        if not spec:
            for c in [*el.classes(), *(x for n in el.find_all("code") for x in n.classes())]:
                if c.startswith(("language-", "lang-")):
                    lang, known = mdtext.brush_language(c.split("-", 1)[1])
        if not known:
            self.hooks.warn(f"code language {lang!r} not recognised, kept as written", el.line)
        if not spec and any("href" in a.attrs for a in el.find_all("a")):
            return self.raw(el)  # preformatted text with links: Markdown code would lose them
        typed: list[str] = []
        code = self._code_text(el.children, literal=bool(spec), typed=typed)
        if typed:
            names = ", ".join(f"<{t}>" for t in sorted(set(typed)))
            self.hooks.warn(f"markup inside code kept as literal text: {names}", el.line)
        return self._code_block(code, lang, el.line)

    def _code_block(self, code: str, lang: str, line: int) -> str:
        code = code.replace("\xa0", " ").replace("\r", "")
        if code.startswith("\n"):
            code = code[1:]  # HTML ignores a newline right after <pre>
        code = code.rstrip("\n")
        if not code.strip():
            return ""
        if self._nested:
            if lang:
                self.hooks.warn(f"code block inside a list or quote: language {lang!r} not kept", line)
            return mdtext.indented_code(code)
        return mdtext.code_fence(code, lang)

    def _code_text(self, nodes: list[Node], literal: bool, typed: list[str]) -> str:
        parts: list[str] = []
        for node in nodes:
            if isinstance(node, Text):
                parts.append(node.data)
            elif isinstance(node, Comment):
                if literal:
                    parts.append(f"<!--{node.data}-->")
                    typed.append("!--")
            elif node.tag == "br":
                parts.append("\n")
            elif literal and node.tag not in CODE_FORMATTING:
                typed.append(node.tag)
                inner = self._code_text(node.children, literal, typed)
                end = "" if node.tag in VOID else f"</{node.tag}>"
                parts.append(node.raw_start + inner + end)
            else:
                parts.append(self._code_text(node.children, literal, typed))
        return "".join(parts)

    def highlighter(self, el: Element) -> str | None:
        """A pasted, already-rendered SyntaxHighlighter table -> the code it shows."""
        names = [c for c in el.classes() if c not in ("syntaxhighlighter", "nogutter", "collapsed", "ie")]
        lang = mdtext.brush_language(names[0])[0] if names else ""
        cells = [td for td in el.find_all("td") if "code" in td.classes()]
        if not cells:
            return None
        lines = [d for d in cells[0].walk() if isinstance(d, Element) and "line" in d.classes()]
        if not lines:
            return None
        code = "\n".join(d.text() for d in lines)
        self.hooks.warn("rendered SyntaxHighlighter table turned back into a code block "
                        "(line numbers dropped)", el.line)
        return self._code_block(code, lang, el.line)

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
        grid = [[c for c in tr.children if isinstance(c, Element) and c.tag in ("td", "th")] for tr in rows]
        grid = [r for r in grid if r]
        if not grid:
            return ""
        for cell in (c for r in grid for c in r):
            spans = cell.attrs.get("rowspan", "1").strip() + cell.attrs.get("colspan", "1").strip()
            blocky = [n for n in cell.walk() if isinstance(n, Element) and n.tag in BLOCKS and n.tag != "p"]
            if spans != "11" or blocky or len(cell.find_all("p")) > 1:
                return self.raw(el)
        width = max(len(r) for r in grid)
        self._in_table = True
        try:
            text = [[self.inline(self._cell_nodes(c), single_line=True).strip() for c in r] for r in grid]
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
        return [n for c in cell.children for n in (c.children if isinstance(c, Element) and c.tag == "p" else [c])]

    # -- raw HTML -----------------------------------------------------------------------
    def raw(self, el: Element) -> str:
        html = to_html(el, self._rewrite_attr).strip()
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
        trail = inner[len(inner.rstrip(" \n")):]
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
        url = self.hooks.url(href, el, "href")
        if self._in_table:
            url = url.replace("|", "%7C")
        plain = mdtext.collapse_ws(el.text()).strip()
        if (plain == href == url and len(el.children) == 1 and isinstance(el.children[0], Text)
                and re.fullmatch(r"https?://[^\s<>|]+", href) and not el.attrs.get("title")):
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
        new = self.hooks.data_image(src, el) if src.startswith("data:") else self.hooks.url(src, el, "src")
        if new is None:
            return ""
        alt = el.attrs.get("alt", "")
        title = el.attrs.get("title", "")
        extra = {k: el.attrs[k] for k in ("width", "height", "style") if el.attrs.get(k, "").strip()}
        if extra:
            attrs = {"src": new, "alt": alt, **({"title": title} if title else {}), **extra}
            return to_html(Element("img", attrs))
        return f"![{mdtext.escape_alt(alt)}]({mdtext.link_destination(new)}{mdtext.link_title(title)})"
