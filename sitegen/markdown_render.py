"""Markdown -> HTML fragments, table of contents and plain text, one page at a time.

The result depends only on the page's own source, so it is cached by the source's hash.
Links are left as the author wrote them (``../w2/index.md``) and directives as markers;
both are resolved later against the whole site by :mod:`sitegen.links`, which is cheap.
"""

from __future__ import annotations

import contextlib
import html
import re
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import markdown
from markdown.extensions import Extension, codehilite
from markdown.extensions.admonition import AdmonitionExtension
from markdown.extensions.attr_list import AttrListExtension
from markdown.extensions.codehilite import CodeHiliteExtension
from markdown.extensions.def_list import DefListExtension
from markdown.extensions.fenced_code import FencedCodeExtension
from markdown.extensions.md_in_html import MarkdownInHtmlExtension
from markdown.extensions.sane_lists import SaneListExtension
from markdown.extensions.tables import TableExtension
from markdown.extensions.toc import TocExtension
from markdown.preprocessors import Preprocessor
from pygments.lexers import find_lexer_class_by_name, get_lexer_by_name
from pygments.util import ClassNotFound
from pymdownx.tabbed import TabbedExtension

from sitegen.highlight_cache import BLOCKS, LazyLexer
from sitegen.markdown_speed import (
    LinearBlocksExtension,
    LinearFootnotesExtension,
    SkippingInlineExtension,
    cached_formatter,
)
from sitegen.md_nested_fences import NestedFencesExtension
from sitegen.slugs import heading_id


def render_key() -> str:
    """Part of every cached fragment's and highlighted block's key: the code that renders
    (this module's import closure, Python-Markdown and Pygments among it;
    :mod:`located.code_keys`), so that no edit or upgrade is served from an older cache."""
    from located.code_keys import code_key

    return code_key(__name__)


DIRECTIVE = re.compile(r"^:::[ \t]*([a-z][a-z0-9-]*)[ \t]+(\S.*?)[ \t]*$")
MARKER = re.compile(r"<!--sitegen:([a-z][a-z0-9-]*):(.*?)-->")
_TAGS = re.compile(r"<[^>]+>")
_ANCHOR = re.compile(r'<a class="anchor"[^>]*>.*?</a>')
_SCRIPT = re.compile(r"<(script|style)\b.*?</\1>", re.S)
_INLINE_TAGS = re.compile(
    r"</?(?:span|code|strong|em|b|i|a|sup|sub|mark|small|abbr|kbd|s|u)\b[^>]*>"
)
_FENCE = re.compile(r"^\s*(```|~~~)")


@dataclass
class Rendered:
    """What a page's Markdown turned into."""

    html: str
    toc: list[dict]  # [{"id", "title", "level", "children": [...]}] for h2/h3
    ids: list[str]  # every id in the fragment (anchor targets)
    text: str  # plain text for search
    directives: list[tuple[str, str, int]] = field(default_factory=list)  # (name, arg, line)
    #: keys of its highlighted code blocks in the store (sitegen.highlight_cache)
    highlights: tuple[str, ...] = ()


class _Directives(Preprocessor):
    """``::: clip NAME`` on a line of its own -> a marker that survives Markdown."""

    def __init__(self, md: markdown.Markdown, found: list):
        super().__init__(md)
        self.found = found

    def run(self, lines: list[str]) -> list[str]:
        out, in_fence = [], False
        for number, line in enumerate(lines, 1):
            if _FENCE.match(line):
                in_fence = not in_fence
            m = None if in_fence else DIRECTIVE.match(line)
            if m:
                name, arg = m.group(1), m.group(2)
                self.found.append((name, arg, number))
                marker = f"<!--sitegen:{name}:{html.escape(arg, quote=True)}-->"
                out.extend(["", self.md.htmlStash.store(marker), ""])
            else:
                out.append(line)
        return out


class DirectiveExtension(Extension):
    def __init__(self, found: list, **kwargs):
        self.found = found
        super().__init__(**kwargs)

    def extendMarkdown(self, md: markdown.Markdown) -> None:  # noqa: N802 (Markdown API)
        md.preprocessors.register(_Directives(md, self.found), "sitegen_directives", 27)


_LEXERS: dict[tuple[str, str], Any] = {}
_LANG = re.compile(r"^[ \t]*(?:```|~~~)[ \t]*\{?[ \t]*\.?([\w+#.-]+)", re.M)


def cached_lexer(alias: str, **options: Any) -> Any:
    """``get_lexer_by_name`` for codehilite, one (lazy) lexer per language and options.

    Pygments looks a name up by scanning its whole table of ~600 lexers, and an unknown
    name also by asking every installed plugin; codehilite did that for every code block
    (a tenth of a cold build). A lexer keeps no state between ``get_tokens`` calls, so one
    instance serves every block of its language; the output is the same. The instance is a
    :class:`~sitegen.highlight_cache.LazyLexer`: a block found in the highlight cache needs no
    lexer, and making the first one of a language compiles its rules."""
    key = (alias, repr(sorted(options.items())))
    found = _LEXERS.get(key)
    if found is None:
        try:
            found = LazyLexer(find_lexer_class_by_name(alias), options)
        except ClassNotFound as exc:
            found = str(exc)
        _LEXERS[key] = found
    if isinstance(found, str):
        raise ClassNotFound(found)
    return found


def warm_lexers(texts: Iterable[str]) -> None:
    """Make the lexers of the fenced code in ``texts`` now, before workers are forked, so each
    worker inherits them compiled (Pygments compiles a lexer's rules on first use: ~50 ms for
    Python) instead of compiling them again. Only the default options are warmed."""
    from sitegen.regex_lexing import prepare

    for lang in sorted({m.lower() for text in texts for m in _LANG.findall(text)}):
        with contextlib.suppress(Exception):  # a bad name fails again, reported, in the page
            lexer = get_lexer_by_name(lang)
            lexer.get_tokens("")
            prepare(lexer)  # and read its rules for sitegen.regex_lexing


codehilite.get_lexer_by_name = cached_lexer  # the names codehilite calls, per code block
codehilite.highlight = BLOCKS.highlight


def _heading_slug(value: str, separator: str) -> str:
    return heading_id(html.unescape(_TAGS.sub("", value)), separator)


class MarkdownRenderer:
    """A reusable Markdown converter (building one per page is slow)."""

    def __init__(self) -> None:
        self._found: list = []
        # extension objects, not names: a name makes Markdown scan the installed packages'
        # entry points (~20 ms per process)
        self.md = markdown.Markdown(
            extensions=[
                TableExtension(),
                FencedCodeExtension(),
                LinearFootnotesExtension(),
                AttrListExtension(),
                DefListExtension(),
                SaneListExtension(),
                MarkdownInHtmlExtension(),
                CodeHiliteExtension(
                    css_class="highlight",
                    guess_lang=False,
                    wrapcode=True,
                    pygments_formatter=cached_formatter,
                ),
                TocExtension(
                    slugify=_heading_slug,
                    toc_depth="2-6",
                    permalink="#",
                    permalink_class="anchor",
                    permalink_title="",
                ),
                DirectiveExtension(self._found),
                AdmonitionExtension(),  # !!! note|tip|warning "title" (reader, issue 17)
                TabbedExtension(),  # === "Windows" content tabs (pymdown-extensions)
                NestedFencesExtension(),  # fenced code inside tabs and admonitions
                LinearBlocksExtension(),  # blocks as a queue: linear in the page's size
                SkippingInlineExtension(),  # prose without any inline markup skipped at once
            ],
            output_format="html",
        )
        # the speed extensions read their patterns on the first page: do it now, so worker
        # processes forked after this inherit it (sitegen.markdown_stage)
        self.render("sitegen")

    def render(
        self, text: str, strip_first_heading: bool = False, strip_html: bool = False
    ) -> Rendered:
        """``strip_html``: the fragment cleaned of raw HTML (sitegen/html_clean.py)."""
        if strip_first_heading:
            text = _drop_first_heading(text)
        self._found.clear()
        self.md.reset()
        BLOCKS.take_used()
        body = self.md.convert(text)
        if strip_html:
            from sitegen.html_clean import strip_raw_html

            body = strip_raw_html(body)
        tokens = getattr(self.md, "toc_tokens", [])
        toc = _toc(tokens)
        ids = re.findall(r'\sid="([^"]+)"', body)
        blocks = tuple(dict.fromkeys(BLOCKS.take_used()))
        return Rendered(body, toc, ids, plain_text(body), list(self._found), blocks)


def _drop_first_heading(text: str) -> str:
    lines = text.split("\n")
    for i, line in enumerate(lines):
        if line.strip():
            if line.lstrip().startswith("# "):
                lines[i] = ""
            break
    return "\n".join(lines)


def _toc(tokens: list[dict]) -> list[dict]:
    """Keep h2 and h3 for the on-page table of contents."""
    out: list[dict] = []

    def visit(items: list[dict]) -> None:
        for t in items:
            if t["level"] == 2:
                out.append({"id": t["id"], "title": html.unescape(t["name"]), "children": []})
            elif t["level"] == 3 and out:
                out[-1]["children"].append(
                    {"id": t["id"], "title": html.unescape(t["name"]), "children": []}
                )
            elif t["level"] == 3:
                out.append({"id": t["id"], "title": html.unescape(t["name"]), "children": []})
            visit(t.get("children", []))

    visit(tokens)
    return out


def plain_text(fragment: str) -> str:
    """Visible text of an HTML fragment, whitespace collapsed (for search and snippets)."""
    fragment = _ANCHOR.sub("", fragment)
    fragment = _SCRIPT.sub(" ", fragment)
    fragment = _INLINE_TAGS.sub("", fragment)
    # str.split() splits at exactly the characters ``\s`` matches, and is far quicker than a
    # regular expression over CJK text
    return " ".join(html.unescape(_TAGS.sub(" ", fragment)).split())
