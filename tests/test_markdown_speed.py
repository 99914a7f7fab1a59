"""The Markdown stage's shortcuts change no output (sitegen.markdown_speed, plain_text).

Each test renders with the shortcut and without it (Python-Markdown's own inline step and
block loop) and compares the bytes: inline patterns skipped on text that cannot hold them,
the block under test read once per round, block tests' searches skipped on text that cannot
hold a match, and the search text's whitespace collapsed without a regular expression.
"""

from __future__ import annotations

import html
import re

from hypothesis import given, settings
from hypothesis import strategies as st
from markdown.treeprocessors import InlineProcessor

from sitegen.markdown_render import MarkdownRenderer, plain_text
from sitegen.markdown_speed import NeedlePattern, SkippingInlineProcessor
from sitegen.regex_starts import required_needles

DOCS = [
    "純中文段落, 沒有任何標記. 第二句話.\n\n第二段 GitHub 與 CoppeliaSim.",
    "*em* **strong** ***both*** _u_ __uu__ a*b*c snake_case_name 2*3*4\n\n* item\n* item2",
    "a [link](x.md) and [another] [ref]\n\n[ref]: https://example.org",
    "`code` ``co`de`` \\`not code\\` \\*not em\\* a\\\\b \\[x\\]",
    "[link](../w2/index.md#齒輪) [ref][r] [r] ![img](a.png) ![ref img][r] <https://x.org>"
    " <me@x.org>\n\n[r]: https://example.org 'T'",
    "line with break  \nnext line\ttab &amp; &copy; &#169; &#xA9; & alone < alone > 3",
    "<span class='x'>inline *html*</span> <!-- comment --> <b>bold</b>",
    "Footnote[^1] and[^n] again[^1].\n\n[^1]: One.\n[^n]: Two with `code`.",
    "## 齒輪 方向 {: #gear .big }\n\nPara {: .cls }\n\n### Sub `code` *em*",
    "| a | b |\n|---|:-:|\n| `x|y` | 2 |\n| \\| | *e* |\n\nnot | a table",
    "Term\n:   definition *em*\n\n: not a def",
    "> quote *em*\n> more\n\n>no space\n\n    indented code *not em*",
    "Setext\n======\n\nSub\n---\n\n---\n\n***\n\n_ _ _\n\n- - -\n\n-- not hr",
    "1. one\n2. two\n    - nested\n    - n2\n\n3) paren\n\n+ plus\n+ plus2",
    '!!! note\n    Note *em* body.\n\n!!! warning "推送之前"\n    ```python\n    x = 1\n    ```',
    '=== "Windows"\n    `py -m pip`\n\n=== "Linux"\n    *python3*\n\n!!!no admonition',
    '<div markdown="1">*inside html* [l](x.md)</div>\n\n<div>raw *not*</div>',
    "::: clip arm\n\nText after ::: not a directive\n\n```\n::: clip in code\n```",
    "# Heading\n\nx  \n\n  \n\n\n",
    "",
]


def _stock_renderer() -> MarkdownRenderer:
    """The same renderer with Python-Markdown's own inline step and block loop."""
    renderer = MarkdownRenderer()
    md = renderer.md
    md.treeprocessors.register(InlineProcessor(md), "inline", 20)
    del md.parser.parseBlocks  # the class's loop: no block read once, no needles
    return renderer


def _same(doc: str, ours: MarkdownRenderer, stock: MarkdownRenderer) -> None:
    a, b = ours.render(doc), stock.render(doc)
    assert (a.html, a.toc, a.ids, a.text, a.directives) == (
        b.html,
        b.toc,
        b.ids,
        b.text,
        b.directives,
    ), doc


#: Reused across examples (a renderer is reset for every page, as in a build).
_PAIR = (MarkdownRenderer(), _stock_renderer())
_STOCK = _PAIR[1]


def test_renderer_uses_the_shortcuts():
    md = MarkdownRenderer().md
    assert isinstance(md.treeprocessors["inline"], SkippingInlineProcessor)
    md.convert("> quote")
    quote = md.parser.blockprocessors["quote"]
    assert isinstance(quote.RE, NeedlePattern)  # '>' looked for before the search


def test_documents_render_as_without_the_shortcuts():
    ours, stock = MarkdownRenderer(), _stock_renderer()
    for doc in DOCS + ["\n\n".join(DOCS)]:
        _same(doc, ours, stock)


@settings(max_examples=250, deadline=None)
@given(
    st.lists(
        st.sampled_from(
            [
                "*",
                "_",
                "`",
                "\\",
                "[",
                "]",
                "(",
                ")",
                "!",
                "<",
                ">",
                "&",
                "#",
                "|",
                ":",
                "-",
                "=",
                "+",
                "1.",
                "^",
                "{",
                "}",
                "  \n",
                "\n",
                "\n\n",
                "    ",
                " ",
                "a",
                "字",
                "x.md",
                "amp;",
                "!!! note",
                '=== "t"',
                "[^1]",
                "[^1]: n",
                "---",
            ]
        ),
        max_size=40,
    )
)
def test_any_markup_soup_renders_as_without_the_shortcuts(parts):
    _same("".join(parts), *_PAIR)


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet=" \t\n>:#|*-_=!`\\[]^a字12.", max_size=50))
def test_block_patterns_find_what_they_found(text):
    for processor in _STOCK.md.parser.blockprocessors:
        for name in dir(processor):
            pattern = getattr(processor, name, None)
            if isinstance(pattern, re.Pattern) and required_needles(pattern):
                fast = NeedlePattern(pattern, required_needles(pattern))
                assert bool(fast.search(text)) == bool(pattern.search(text)), (name, text)
                assert [m.span() for m in fast.finditer(text)] == [
                    m.span() for m in pattern.finditer(text)
                ]


def _plain_text_by_regex(fragment: str) -> str:
    fragment = re.sub(r'<a class="anchor"[^>]*>.*?</a>', "", fragment)
    fragment = re.sub(r"<(script|style)\b.*?</\1>", " ", fragment, flags=re.S)
    fragment = re.sub(
        r"</?(?:span|code|strong|em|b|i|a|sup|sub|mark|small|abbr|kbd|s|u)\b[^>]*>", "", fragment
    )
    text = html.unescape(re.sub(r"<[^>]+>", " ", fragment))
    return re.sub(r"\s+", " ", text).strip()


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet=" \t\n\r\x0b\x0c\x1c\x85\xa0\u2003\u3000\u200b<>/pa字&;nbsp", max_size=60))
def test_search_text_collapses_whitespace_as_the_regex_did(fragment):
    assert plain_text(fragment) == _plain_text_by_regex(fragment)
