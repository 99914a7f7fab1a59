"""``sitegen check``: verify a built site offline, as a browser would follow it.

Every internal ``href``/``src``/``poster`` must name a file in the site, every ``#anchor`` an
id on the target page. External URLs (a YouTube iframe, an image on another site) are
checked for form only -- a scheme and a host, parsed with the same rule as the build
(:func:`sitegen.links.external_problem`) -- and never fetched, so ``sitegen check`` and
``sitegen build --strict`` agree. A protocol-relative ``//host/...`` URL is reported: from
``file://`` it names a file (the build writes ``https://`` instead).
"""

from __future__ import annotations

import os
import posixpath
from collections.abc import Callable
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

from sitegen.links import external_problem


class _Collector(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.ids: set[str] = set()
        self.refs: list[tuple[str, str, str, int]] = []  # (tag, attr, url, line)

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        line = self.getpos()[0]
        for name, value in attrs:
            if value is None:
                continue
            if name in ("id", "name") and (name == "id" or tag == "a"):
                self.ids.add(value)
            if name in ("href", "src", "poster"):
                if tag == "base":
                    continue
                self.refs.append((tag, name, value, line))


def _parse(path: Path) -> _Collector:
    c = _Collector()
    c.feed(path.read_text(encoding="utf-8", errors="replace"))
    c.close()
    return c


def check_site(site_dir: Path, log: Callable[[str], None] | None = None) -> list[str]:
    """Return one line per problem, ``file:line: message``; empty when the site is sound.
    ``log`` (``check -v``) hears each page checked with what it links to."""
    site_dir = site_dir.resolve()
    if not site_dir.is_dir():
        return [f"{site_dir}: not a folder (build the site first)"]
    problems: list[str] = _symlinks(site_dir)
    pages = sorted(p for p in site_dir.rglob("*.html") if p.is_file() and not p.is_symlink())
    parsed = {p.relative_to(site_dir).as_posix(): _parse(p) for p in pages}
    for rel, c in parsed.items():
        if rel == "404.html":
            if log:
                log(f"  {rel}: not checked (served at any depth; its links use <base href>)")
            continue  # served at any depth by GitHub Pages; its links use <base href>
        outside = 0
        for tag, attr, url, line in c.refs:
            problem = _check_ref(site_dir, parsed, rel, c, tag, attr, url)
            outside += _leaves_site(url)
            if problem:
                problems.append(f"{rel}:{line}: {problem}")
        if log:
            log(
                f"  {rel}: {len(c.refs) - outside} links in the site, {outside} outside it "
                f"(form only), {len(c.ids)} ids"
            )
    if log:
        files = sum(1 for p in site_dir.rglob("*") if p.is_file())
        log(f"  {len(parsed)} pages, {files} files")
    return problems


def _leaves_site(url: str) -> bool:
    """A link to another site (a scheme, or ``//host``); a URL too malformed to split (an
    unclosed ``[`` host) is not one of the site's own files either."""
    try:
        return bool(urlsplit(url).scheme) or url.startswith("//")
    except ValueError:
        return True


def _symlinks(site_dir: Path) -> list[str]:
    """Any symlink in a site is a problem: a Pages upload (or a web server) follows it and
    publishes whatever it points to. ``sitegen build`` never writes one."""
    found = []
    for dirpath, dirnames, filenames in os.walk(site_dir):
        for name in sorted(dirnames + filenames):
            path = Path(dirpath) / name
            if path.is_symlink():
                rel = path.relative_to(site_dir).as_posix()
                found.append(f"{rel}: is a symlink (to {os.readlink(path)}); publish files only")
    return found


def _check_ref(
    site_dir: Path,
    parsed: dict[str, _Collector],
    rel: str,
    c: _Collector,
    tag: str,
    attr: str,
    url: str,
) -> str | None:
    problem = external_problem(url)
    if problem:
        return f"<{tag} {attr}>: {problem}"
    if url.startswith("//"):
        return f"<{tag} {attr}> '{url}' is protocol-relative: from file:// it names a file"
    parts = urlsplit(url)
    if parts.scheme:
        return None
    if not parts.path:
        if parts.fragment and unquote(parts.fragment) not in c.ids:
            return f"anchor '#{unquote(parts.fragment)}' not found on this page"
        return None
    target = posixpath.normpath(posixpath.join(posixpath.dirname(rel), unquote(parts.path)))
    if target.startswith(".."):
        return f"'{url}' points outside the site"
    path = site_dir / target
    if path.is_dir():
        return f"'{url}' names a folder; links must name the file (index.html) to work from file://"
    if not path.is_file():
        return f"'{url}' not found"
    if parts.fragment and target in parsed and unquote(parts.fragment) not in parsed[target].ids:
        return f"anchor '#{unquote(parts.fragment)}' not found in '{target}'"
    return None
