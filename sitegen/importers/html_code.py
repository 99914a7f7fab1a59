"""Code in cmsimde pages: ``<pre class="brush:py">`` blocks and pasted highlighter output.

cmsimde's editor inserts code as ``<pre class="brush:LANG;...">`` for SyntaxHighlighter,
which reads the block's *source*, so tags a student typed unescaped inside it (``<ui>`` in a
Lua string) were meant as code: they are kept as literal text. Some students pasted the
already-highlighted result (a table of line numbers and ``<div class="line">``); that is
turned back into the code it shows.
"""

from __future__ import annotations

import re

from sitegen.importers import mdtext
from sitegen.importers.htmltree import VOID, Comment, Element, Node, Text

#: Formatting a highlighter may leave inside <pre>; any other tag there was typed code.
CODE_FORMATTING = {
    "span",
    "code",
    "b",
    "strong",
    "i",
    "em",
    "a",
    "font",
    "u",
    "mark",
    "sub",
    "sup",
    "s",
    "small",
    "big",
}
_NOT_LANGUAGE = {"syntaxhighlighter", "nogutter", "collapsed", "ie"}


def pre_language(el: Element) -> tuple[str, bool, bool]:
    """(fenced-code language, known?, has a SyntaxHighlighter brush?) for a ``<pre>``."""
    m = re.search(r"brush\s*:\s*([^;\s]+)", el.attrs.get("class", ""))
    if m:
        return (*mdtext.brush_language(m.group(1)), True)
    for c in [*el.classes(), *(x for n in el.find_all("code") for x in n.classes())]:
        if c.startswith(("language-", "lang-")):
            return (*mdtext.brush_language(c.split("-", 1)[1]), False)
    return "", True, False


def code_text(nodes: list[Node], literal: bool, typed: list[str]) -> str:
    """The text a code block shows; with ``literal``, typed tags and comments are kept.

    Names of the tags kept literally are appended to ``typed`` for the report.
    """
    parts: list[str] = []
    for node in nodes:
        if isinstance(node, Text):
            parts.append(node.data)
        elif isinstance(node, Comment):
            if literal:
                parts.append(f"<!--{node.data}-->")
                typed.append("!-- --")
        elif node.tag == "br":
            parts.append("\n")
        elif literal and node.tag not in CODE_FORMATTING:
            typed.append(node.tag)
            end = "" if node.tag in VOID else f"</{node.tag}>"
            parts.append(node.raw_start + code_text(node.children, literal, typed) + end)
        else:
            parts.append(code_text(node.children, literal, typed))
    return "".join(parts)


def code_block(code: str, lang: str, nested: bool) -> str:
    """Fenced code, or indented code inside lists and quotes where fences are not read."""
    code = code.replace("\xa0", " ").replace("\r", "")
    if code.startswith("\n"):
        code = code[1:]  # HTML ignores a newline right after <pre>
    code = code.rstrip("\n")
    if not code.strip():
        return ""
    return mdtext.indented_code(code) if nested else mdtext.code_fence(code, lang)


def highlighter_code(el: Element) -> tuple[str, str] | None:
    """(code, language) shown by a rendered ``<div class="syntaxhighlighter LANG">``."""
    names = [c for c in el.classes() if c not in _NOT_LANGUAGE]
    lang = mdtext.brush_language(names[0])[0] if names else ""
    cells = [td for td in el.find_all("td") if "code" in td.classes()]
    if not cells:
        return None
    lines = [d for d in cells[0].walk() if isinstance(d, Element) and "line" in d.classes()]
    if not lines:
        return None
    return "\n".join(d.text() for d in lines), lang
