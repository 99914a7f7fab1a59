"""Old URLs that keep working: ``aliases:`` become redirect pages; a moved page is reported.

A page's URL is slugged from its title (docs/authoring.md), so editing a heading moves the
page and breaks every link to it from outside the site (a classmate's page, a bookmark, a
search engine). Two things help, as in Hugo: a page lists its old URLs under ``aliases:``
and each becomes a small page that sends the reader on (``<meta http-equiv="refresh">``, a
canonical link, a plain link for readers without refresh, ``noindex`` for search engines);
and the build remembers every content page's URL (``urls.json`` in the cache folder) so
the next build can warn, naming the alias to add, when a page's URL has changed.

All hrefs are relative, so the redirects work under a GitHub Pages project prefix
(``https://user.github.io/repo/``) and from ``file://``.
"""

from __future__ import annotations

import json
import os
import re
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote

from located.diagnostics import quoted
from sitegen.config import Config
from sitegen.errors import Diagnostics
from sitegen.integrations import Built, Integration
from sitegen.links import relative, url_quote
from sitegen.nav import Node

HISTORY_FILE = "redirects-urls.json"
HISTORY_FORMAT = 1
TEMPLATE = "redirect.html"

#: top folders the build fills itself (nav.RESERVED_ROOT's folders) and its root files
_BUILD_FOLDERS = ("assets", "clips", "roster")
_BUILD_FILES = ("404.html", "search.html", "sitemap.html", "sitemap.xml", "feed.xml")
_SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")
_MAX_SEGMENT = 255  # bytes in a file name on common file systems


@dataclass(frozen=True)
class Alias:
    """One old URL of a page, where it was written, and the file that will redirect."""

    file: str  # the page's file as the user names it, e.g. content/week-1.md
    line: int | None
    raw: str  # as written in the front matter
    path: str  # output path of the redirect page, e.g. old/name.html
    node: Node  # the page it leads to


def alias_path(raw: str) -> tuple[str | None, str | None]:
    """The output file for an old URL as an author writes it, or why it cannot be one.

    ``old.html`` and ``/old.html`` (site-root, as Hugo writes them) -> ``old.html``;
    ``old/`` and ``old`` -> ``old/index.html``; percent-escapes are decoded (a URL copied
    from the address bar names the same file). Returns (path, None) or (None, problem)."""
    text = raw.strip()
    if not text:
        return None, "is empty"
    if any(ord(c) < 0x20 or c == "\x7f" for c in text) or "\\" in text:
        return None, "contains a control character or a backslash"
    if text.startswith("//"):
        return None, "names another host; an alias is a path inside this site"
    if _SCHEME.match(text):
        return None, "is a full URL with a scheme; write the old path inside this site"
    if "?" in text or "#" in text:
        return None, "has a query or fragment; only a path can be redirected"
    path = unquote(text)
    if any(ord(c) < 0x20 or c == "\x7f" for c in path) or "\\" in path:
        return None, "decodes to a control character or a backslash"
    is_dir = path.endswith("/")
    parts = path.strip("/").split("/") if path.strip("/") else []
    for part in parts:
        if part in ("", ".", ".."):
            return None, "is not a plain relative path (no '..', '.' or empty parts)"
        if len(part.encode()) > _MAX_SEGMENT:
            return None, f"has a part longer than {_MAX_SEGMENT} bytes"
    if not is_dir and parts and parts[-1].lower().endswith((".html", ".htm")):
        return "/".join(parts), None
    return "/".join([*parts, "index.html"]), None


def _reserved(path: str) -> str | None:
    """Why the build itself owns ``path`` (theme assets, clips, special pages), or None."""
    top = path.split("/", 1)[0]
    if "/" in path and top in _BUILD_FOLDERS:
        return f"is inside '{top}/', which the build fills"
    if path in _BUILD_FILES or path.endswith(".slides.html"):
        return "is the path of a page the build makes"
    return None


def alias_lines(source: Path, body_line: int) -> dict[str, int]:
    """Line of each alias in a page's front matter, read again from the file: the front matter
    record keeps values, not lines, and only pages with aliases pay for this (YAML too is
    imported only then)."""
    import yaml

    from located import yaml as located_yaml
    from located.yamlwalk import Walker

    try:
        raw = source.read_bytes().decode("utf-8-sig").replace("\r\n", "\n").replace("\r", "\n")
        lines = raw.split("\n")
        node = located_yaml.compose(
            "\n".join(lines[1 : max(1, body_line - 2)]), str(source), first_line=2
        )
    except (OSError, UnicodeDecodeError, located_yaml.YamlError):
        return {}
    found: dict[str, int] = {}
    if not isinstance(node, yaml.MappingNode):
        return found
    walk = Walker(str(source), first_line=2)  # problems were reported when the page was read
    for key, key_node, value in walk.mapping(node, "front matter"):
        if key != "aliases":
            continue
        items = value.value if isinstance(value, yaml.SequenceNode) else [value]
        for item in items:
            if isinstance(item, yaml.ScalarNode):
                for text in str(item.value).split(","):
                    found.setdefault(text.strip(), walk.line(item) or 1)
        found.setdefault("", walk.line(key_node) or 1)
    return found


class RedirectIntegration(Integration):
    """Redirect pages for ``aliases:``, and a warning when a page's URL changed."""

    def __init__(self, config: Config, cache_dir: Path):
        self.config = config
        self.history_file = cache_dir / HISTORY_FILE
        self.urls: dict[str, str] | None = None  # content file -> URL, set by site_files

    def _history(self) -> dict[str, str]:
        try:
            raw = json.loads(self.history_file.read_text(encoding="utf-8"))
            urls = raw["urls"] if raw.get("format") == HISTORY_FORMAT else {}
            return {str(k): str(v) for k, v in urls.items()}
        except (OSError, ValueError, KeyError, TypeError, AttributeError):
            return {}  # unreadable: no history, so no warnings; the next build writes it anew

    def aliases(self, built: Built) -> list[Alias]:
        """Every alias of every content page, in document order, with its line."""
        out = []
        for node in built.site.order:
            src = node.source
            if src is None or not src.meta.get("aliases"):
                continue
            lines = alias_lines(self.config.content_path / src.rel, src.body_line)
            file = f"{built.content_name}/{src.rel}"
            for raw in src.meta["aliases"]:
                path, _ = alias_path(raw)
                out.append(Alias(file, lines.get(raw, lines.get("")), raw, path or "", node))
        return out

    def site_files(self, built: Built, diags: Diagnostics) -> dict[str, bytes]:
        pages = {n.url: n for n in built.site.order}
        assets = {str(a) for a in built.targets.assets}
        made: dict[str, Alias] = {}
        for alias in self.aliases(built):
            problem = alias_path(alias.raw)[1] or _reserved(alias.path)
            if problem is None and alias.path in pages:
                other = pages[alias.path]
                whose = "this page" if other is alias.node else f"the page {quoted(other.title)}"
                problem = f"is the URL of {whose} ({alias.path}); an alias must be an old URL"
            elif problem is None and alias.path in assets:
                problem = f"is the path of the file {built.content_name}/{alias.path}"
            elif problem is None and alias.path in made:
                first = made[alias.path]
                where = f"{first.file}:{first.line}" if first.line else first.file
                problem = f"names the same file ({alias.path}) as the alias at {where}"
            if problem:
                diags.error(alias.file, alias.line, "aliases", f"{quoted(alias.raw)} {problem}")
            else:
                made[alias.path] = alias
        self._warn_moved(built, made, diags)
        return {path: self._render(built, a) for path, a in sorted(made.items())}

    def _warn_moved(self, built: Built, made: dict[str, Alias], diags: Diagnostics) -> None:
        """Compare each content page's URL with the last good build's."""
        old = self._history()
        pages = {n.url for n in built.site.order}
        self.urls = {}
        for node in built.site.order:
            src = node.source
            if src is None or src.body_html is not None:  # generated pages have no file
                continue
            rel = str(src.rel)
            self.urls[rel] = node.url
            was = old.get(rel)
            if was is None or was == node.url or was in made or was in pages:
                continue  # new, unchanged, redirected already, or another page lives there now
            diags.warning(
                f"{built.content_name}/{rel}",
                None,
                "url",
                f"URL changed from {was} to {node.url}; add `aliases: [{was}]` to keep old "
                "links working",
            )

    def _render(self, built: Built, alias: Alias) -> bytes:
        href = url_quote(relative(alias.path, alias.node.url))
        base_url = built.base["site"]["base_url"]
        canonical = base_url + url_quote(alias.node.url) if base_url else href
        context = {
            **built.base,
            "root": "../" * alias.path.count("/"),
            "title": alias.node.title,
            "href": href,
            "canonical": canonical,
            "old_path": alias.path,
        }
        return built.theme.render(TEMPLATE, context).encode()

    def save(self, state) -> None:
        """Remember the URLs of this (good) build for the next one's comparison."""
        if self.urls is None:
            return  # the pages were not looked at: keep the history as it is
        data = json.dumps(
            {"format": HISTORY_FORMAT, "urls": self.urls}, ensure_ascii=False, sort_keys=True
        )
        try:
            self.history_file.parent.mkdir(parents=True, exist_ok=True)
            tmp = self.history_file.with_name(f"{self.history_file.name}.{os.getpid()}.tmp")
            tmp.write_text(data + "\n", encoding="utf-8")
            os.replace(tmp, self.history_file)
        except OSError:
            pass  # an unwritable cache only loses the next build's warning
