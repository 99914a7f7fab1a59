"""Markdown text primitives: escaping, code fences, link destinations, code languages.

The goal is that the built page shows exactly the text the cmsimde page showed. Python-
Markdown (with the extensions sitegen enables: tables, fenced_code, attr_list, def_list,
footnotes, md_in_html) gives meaning to more characters than CommonMark does, so escaping is
done here, in one place, and tested against the real renderer.
"""

from __future__ import annotations

import re

#: Characters Python-Markdown lets a backslash escape.
ESCAPABLE = frozenset("\\`*_{}[]()>#+-.!")
_ENTITY = re.compile(r"&(#\d+|#[xX][0-9a-fA-F]+|[A-Za-z][A-Za-z0-9]*);")
_NBSP = "\xa0"


def collapse_ws(text: str) -> str:
    """HTML whitespace collapsing: runs of ASCII whitespace become one space (not nbsp)."""
    return re.sub(r"[ \t\n\r\f]+", " ", text)


def escape_text(text: str) -> str:
    """Escape ``text`` (already whitespace-collapsed) so Markdown shows it literally.

    ``_`` inside a word is left alone (Python-Markdown's smart emphasis ignores it), so
    ``site_title`` stays readable; ``{`` is escaped only when a ``}`` follows, which is what
    attr_list would eat.
    """
    out: list[str] = []
    n = len(text)
    for i, ch in enumerate(text):
        nxt = text[i + 1] if i + 1 < n else ""
        if ch == "\\":
            out.append("\\\\" if (not nxt or nxt in ESCAPABLE) else "\\")
        elif ch in "*`[]":
            out.append("\\" + ch)
        elif ch == "_":
            prev = text[i - 1] if i else ""
            inner = prev.isalnum() and nxt.isalnum()
            out.append("_" if inner else "\\_")
        elif ch == "<":
            out.append("&lt;")
        elif ch == "&":
            out.append("&amp;" if _ENTITY.match(text, i) else "&")
        elif ch == "{":
            out.append("\\{" if "}" in text[i:] else "{")
        elif ch == _NBSP:
            prev = text[i - 1] if i else ""
            lone = prev not in ("", " ", _NBSP) and nxt not in ("", " ", _NBSP)
            out.append(" " if lone else "&nbsp;")
        else:
            out.append(ch)
    return "".join(out)


_LINE_START = [
    (re.compile(r"^(#|>|\+|-)"), lambda m: "\\" + m.group(1)),
    (re.compile(r"^(\d+)\.(?=\s|$)"), lambda m: m.group(1) + "\\."),
    (re.compile(r"^:"), lambda m: "&#58;"),  # def_list, ::: directives
    (re.compile(r"^~(?=~~)"), lambda m: "&#126;"),  # ~~~ fences
    (re.compile(r"^=(?==*\s*$)"), lambda m: "&#61;"),  # setext underline
]


def escape_line_starts(text: str) -> str:
    """Neutralise what Markdown reads at the start of a line; strip spaces around lines.

    Leading spaces are dropped (HTML ignores them, Markdown would read four as code) and
    trailing ones too (two would be a hard break).
    """
    lines = []
    for line in text.split("\n"):
        line = line.strip(" ")
        for pattern, repl in _LINE_START:
            line, count = pattern.subn(repl, line, count=1)
            if count:
                break
        lines.append(line)
    return "\n".join(lines)


def escape_heading_end(text: str) -> str:
    """Python-Markdown strips trailing ``#`` from ATX headings; escape a final one."""
    return text[:-1] + "\\#" if text.endswith("#") and not text.endswith("\\#") else text


def code_span(text: str) -> str:
    """Inline code for ``text``, with a backtick fence longer than any run inside."""
    text = collapse_ws(text)
    if not text.strip():
        return ""
    longest = max((len(r) for r in re.findall(r"`+", text)), default=0)
    fence = "`" * (longest + 1)
    pad = " " if text.startswith("`") or text.endswith("`") else ""
    return f"{fence}{pad}{text}{pad}{fence}"


def code_fence(code: str, lang: str) -> str:
    """A fenced code block; the fence is longer than any backtick run in the code."""
    longest = max((len(r) for r in re.findall(r"`{3,}", code)), default=0)
    fence = "`" * max(3, longest + 1)
    return f"{fence}{lang}\n{code}\n{fence}"


def indented_code(code: str) -> str:
    """An indented code block: the only kind Python-Markdown reads inside lists/quotes."""
    return "\n".join(("    " + line) if line.strip() else "" for line in code.split("\n"))


def link_destination(url: str) -> str:
    """Write ``url`` as a Markdown link destination, keeping spaces and CJK readable."""
    url = url.replace("<", "%3C").replace(">", "%3E")
    if re.search(r"[\s()]", url):
        return f"<{url}>"
    return url


def link_title(title: str) -> str:
    return ' "' + title.replace("\\", "\\\\").replace('"', "&quot;") + '"' if title else ""


def escape_alt(text: str) -> str:
    return collapse_ws(text).replace("\\", "\\\\").replace("[", "\\[").replace("]", "\\]").strip()


def yaml_string(text: str) -> str:
    """A YAML double-quoted scalar for ``text`` that round-trips exactly."""
    out = ['"']
    for ch in text:
        code = ord(ch)
        if ch == '"':
            out.append('\\"')
        elif ch == "\\":
            out.append("\\\\")
        elif code < 0x20 or code == 0x7F or ch in "\x85\u2028\u2029\ufeff":
            out.append(f"\\u{code:04x}")
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


# -- code languages ------------------------------------------------------------------------

#: SyntaxHighlighter brush alias -> fenced-code language (a Pygments lexer name).
BRUSH_LANG = {
    "py": "python",
    "python": "python",
    "js": "javascript",
    "jscript": "javascript",
    "javascript": "javascript",
    "ts": "typescript",
    "typescript": "typescript",
    "html": "html",
    "xhtml": "html",
    "xml": "xml",
    "xslt": "xml",
    "css": "css",
    "lua": "lua",
    "dart": "dart",
    "c": "c",
    "cpp": "cpp",
    "c++": "cpp",
    "h": "c",
    "csharp": "csharp",
    "c#": "csharp",
    "c-sharp": "csharp",
    "java": "java",
    "javafx": "java",
    "jfx": "java",
    "php": "php",
    "bash": "bash",
    "shell": "bash",
    "sh": "bash",
    "plain": "text",
    "text": "text",
    "txt": "text",
    "sql": "sql",
    "ruby": "ruby",
    "rails": "ruby",
    "ror": "ruby",
    "rb": "ruby",
    "perl": "perl",
    "pl": "perl",
    "go": "go",
    "golang": "go",
    "scala": "scala",
    "groovy": "groovy",
    "vb": "vbnet",
    "vbnet": "vbnet",
    "diff": "diff",
    "patch": "diff",
    "ps": "powershell",
    "powershell": "powershell",
    "delphi": "delphi",
    "pascal": "pascal",
    "pas": "pascal",
    "erlang": "erlang",
    "erl": "erlang",
    "as3": "actionscript3",
    "actionscript3": "actionscript3",
    "sass": "sass",
    "scss": "scss",
    "swift": "swift",
    "haxe": "haxe",
    "yaml": "yaml",
    "yml": "yaml",
    "json": "json",
    "matlab": "matlab",
    "r": "r",
    "rust": "rust",
    "kotlin": "kotlin",
    "latex": "latex",
    "tex": "latex",
    "markdown": "markdown",
    "md": "markdown",
    "applescript": "applescript",
    "coldfusion": "cfm",
    "cf": "cfm",
    "tap": "text",
    "bat": "batch",
    "batch": "batch",
    "cmd": "batch",
    "cmake": "cmake",
    "make": "make",
    "makefile": "make",
    "ini": "ini",
}


def brush_language(name: str) -> tuple[str, bool]:
    """A SyntaxHighlighter brush alias (``'js'``, ``'py'``) -> (fenced-code language, known?)."""
    name = name.strip().lower()
    if name in BRUSH_LANG:
        return BRUSH_LANG[name], True
    clean = re.sub(r"[^a-z0-9+#_-]", "", name)
    return clean, False
