"""Resolve the links an author wrote against the site, and report the broken ones.

Authors link to source files (``../w2/index.md#齒輪``, ``images/gear.png``, or cmsimde-style
``/images/gear.png`` from the content root); the output must link to the generated pages with
paths relative to the linking page, so the same site works from ``file://``, under
``https://user.github.io/repo/`` and at a domain root.

Only real attributes of real tags are rewritten: the text of ``<pre>``, ``<code>``, comments,
``<script>`` and ``<style>`` is never touched nor checked, because a code sample that shows
HTML must read exactly as its author wrote it. External URLs are checked for form only (a
scheme and a host; never fetched), with the same rule as ``sitegen check``; a URL that does not
parse is kept as written with a warning. Protocol-relative ``//host/...`` becomes
``https://host/...``: from ``file://`` it would name a file.
"""

from __future__ import annotations

import html
import posixpath
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import PurePosixPath
from urllib.parse import quote, unquote, urlsplit

from sitegen.errors import Diagnostics
from sitegen.nav import Node, Site

_ATTR = re.compile(r"""(\s(?:href|src|poster)=)(["'])(.*?)\2""", re.S)
_SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")
#: Regions whose text is not markup to rewrite: comments and code/raw-text elements.
_OPAQUE = re.compile(
    r"<!--.*?-->|<(pre|code|script|style|textarea)\b[^>]*>.*?</\1\s*>", re.S | re.I
)
#: One start tag; quoted attribute values may hold ``>``.
_TAG = re.compile(r"""<[A-Za-z][^\s/>]*(?:[^>"']|"[^"]*"|'[^']*')*>""")
WEB_SCHEMES = ("http", "https")


def external_problem(url: str) -> str | None:
    """Why an http(s) or ``//host`` URL is malformed (no host, does not parse), or None.

    The only check made on external URLs, by the build and by ``sitegen check`` alike:
    they are never fetched.
    """
    try:
        parts = urlsplit(url)
        parts.port  # noqa: B018 -- raises ValueError for a port that is not a number
    except ValueError as exc:
        return f"malformed URL '{url}' ({exc}); kept as written"
    if (parts.scheme.lower() in WEB_SCHEMES or url.startswith("//")) and not parts.hostname:
        return f"URL '{url}' has no host; kept as written"
    return None


def url_quote(path: str) -> str:
    """Percent-encode a site-relative path for an href (keeps ``/`` and ``#``)."""
    return quote(path, safe="/-._~!$&'()*+,;=:@")


def relative(from_url: str, to_url: str) -> str:
    """Relative URL from the page at ``from_url`` to ``to_url`` (both site-root paths)."""
    start = posixpath.dirname(from_url) or "."
    return posixpath.relpath(to_url, start)


@dataclass
class LinkTargets:
    """What a link may point at: pages by source path and URL, and copied assets."""

    site: Site
    assets: set[PurePosixPath]
    ids: dict[str, set[str]]  # page URL -> anchor ids on that page
    by_url: dict[str, Node]

    @classmethod
    def build(cls, site: Site, assets: set[PurePosixPath], ids: dict[str, set[str]]) -> LinkTargets:
        return cls(site, assets, ids, {n.url: n for n in site.order})

    def resolve(self, node: Node, raw: str) -> tuple[tuple[str, str] | None, str | None]:
        """Return ((site-root path, fragment), problem). Unchanged links give (None, None).

        The path is returned apart from the fragment because a file name may hold ``#``.
        """
        if not raw or _SCHEME.match(raw) or raw.startswith("//"):
            return None, None
        path, _, frag = raw.partition("#")
        path, _, _query = path.partition("?")
        if not path:
            if (
                frag
                and frag not in self.ids.get(node.url, set())
                and unquote(frag) not in self.ids.get(node.url, set())
            ):
                return None, f"anchor '#{unquote(frag)}' not found on this page"
            return None, None
        path = unquote(path)
        if path.startswith("/"):
            joined = path.lstrip("/")
        else:
            base = node.source.rel.parent if node.source else node.rel_dir
            joined = posixpath.join(str(base), path)
        norm = posixpath.normpath(joined)
        if norm.startswith("../") or norm == "..":
            return None, f"link '{raw}' points outside the content folder"
        target_url = self._target(PurePosixPath(norm), path.endswith("/"))
        if target_url is None:
            return None, f"link target '{raw}' does not exist"
        if frag:
            ids = self.ids.get(target_url)
            if ids is not None and frag not in ids and unquote(frag) not in ids:
                return None, f"anchor '#{unquote(frag)}' not found in '{path}'"
        return (target_url, frag), None

    def _target(self, p: PurePosixPath, is_dir: bool) -> str | None:
        site = self.site
        if p == PurePosixPath("."):
            return site.root.url
        if not is_dir:
            if p in site.by_source:
                return site.by_source[p].url
            if p in self.assets:
                return str(p)
            if str(p) in self.by_url:
                return str(p)
        if p in site.by_dir:
            return site.by_dir[p].url
        return None


def line_of(source: str, needle: str, first_line: int) -> int | None:
    at = source.find(needle)
    if at < 0:
        return None
    return first_line + source.count("\n", 0, at)


def rewrite_links(
    fragment: str,
    node: Node,
    targets: LinkTargets,
    diags: Diagnostics,
    file: str,
    source: str = "",
    first_line: int = 1,
) -> str:
    """Rewrite every href/src/poster of the tags in ``fragment`` (never inside code); warn
    about broken or malformed ones with file:line."""

    def sub(m: re.Match) -> str:
        raw = m.group(3).strip()
        if raw.startswith("//") or _SCHEME.match(raw):
            problem = external_problem(html.unescape(raw))
            if problem:
                diags.warning(file, line_of(source, raw, first_line), "link", problem)
                return m.group(0)
            if raw.startswith("//"):
                return f"{m.group(1)}{m.group(2)}https:{raw}{m.group(2)}"
            return m.group(0)
        target, problem = targets.resolve(node, raw)
        if problem:
            diags.warning(file, line_of(source, raw, first_line), "link", problem)
            return m.group(0)
        if target is None:
            return m.group(0)
        path, frag = target
        href = url_quote(relative(node.url, path)) + (f"#{frag}" if frag else "")
        return f"{m.group(1)}{m.group(2)}{href}{m.group(2)}"

    def tag(m: re.Match) -> str:
        return _ATTR.sub(sub, m.group(0))

    out: list[str] = []
    pos = 0
    for opaque in _OPAQUE.finditer(fragment):
        out.append(_TAG.sub(tag, fragment[pos : opaque.start()]))
        out.append(opaque.group(0))
        pos = opaque.end()
    out.append(_TAG.sub(tag, fragment[pos:]))
    return "".join(out)


DirectiveHandler = Callable[[str, Node], str]


def expand_directives(
    fragment: str,
    node: Node,
    handlers: dict[str, DirectiveHandler],
    diags: Diagnostics,
    file: str,
    directives: list[tuple[str, str, int]],
    first_line: int,
) -> str:
    """Replace ``<!--sitegen:NAME:ARG-->`` markers with what the handler for NAME returns."""
    from sitegen.markdown_render import MARKER  # lazily: a no-op build never loads Markdown

    lines = {(name, arg): first_line + line - 1 for name, arg, line in directives}

    def sub(m: re.Match) -> str:
        name, arg = m.group(1), html.unescape(m.group(2))
        handler = handlers.get(name)
        line = lines.get((name, arg))
        if handler is None:
            known = ", ".join(sorted(handlers)) or "none configured"
            diags.error(file, line, f"::: {name}", f"unknown directive (known: {known})")
            return ""
        try:
            return handler(arg, node)
        except LookupError as exc:
            diags.error(file, line, f"::: {name}", str(exc.args[0] if exc.args else exc))
            return ""

    return keep_first_once(MARKER.sub(sub, fragment))


ONCE = re.compile(r'<script data-once="([^"]*)"[^>]*></script>')


def keep_first_once(html_text: str) -> str:
    """Of the ``<script data-once="KEY">`` tags directives put in a page, the first per key
    (a page with three replays loads the viewer once, and so does its slide deck)."""
    if "data-once=" not in html_text:
        return html_text
    seen: set[str] = set()

    def first(m: re.Match) -> str:
        if m.group(1) in seen:
            return ""
        seen.add(m.group(1))
        return m.group(0)

    return ONCE.sub(first, html_text)
