"""An iframed local page (`/downloads/threejs_ex/index.html`) and every file it loads.

A cmsimde page may iframe a demo kept under ``downloads/``: an HTML page that loads its own
CSS, scripts, models and textures by relative URL. Copying the HTML file alone gives a
blank frame (only ``sitegen check`` would notice). So the page is read for what it loads --
``src``, ``href``, ``poster``, ``data`` and ``srcset`` attributes, ``url()`` and ``@import``
in its CSS (files and ``<style>``), and, in its scripts, quoted strings that name an existing
file beside the page or the script (`loader.load('jansen-asm.obj')`, ES module imports,
import maps) -- and each file found is copied too, recursively (a CSS file's images, an
iframed page's own frames). Only files under the site's ``images/``, ``downloads/`` and
``static/`` are copied, as for every other link; references that leave them, or files
that are missing, are reported with the page that names them.

The HTML is read with the standard library's ``html.parser`` and CSS/JS with regular
expressions over their text: enough to find URLs, and nothing here runs or renders them.
"""

from __future__ import annotations

import posixpath
import re
from collections.abc import Callable
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

#: Files worth opening to look for more references (the rest are copied as they are).
_HTML = (".html", ".htm", ".xhtml")
_CSS = (".css",)
_JS = (".js", ".mjs", ".json", ".mtl", ".gltf")
MAX_FILES = 2000  # a demo folder with more than this is reported, not copied past the limit
_CSS_URL = re.compile(r"""url\(\s*(['"]?)([^'")\s]+)\1\s*\)|@import\s+(['"])([^'"]+)\3""")
_JS_STRING = re.compile(r"""(['"`])([^'"`\s\\<>]{1,200}\.[A-Za-z0-9]{1,8})\1""")
_MTL_MAP = re.compile(r"^\s*(?:map_\w+|bump|disp|decal|norm)\s+(?:-\S+\s+\S+\s+)*(\S+)\s*$", re.M)


class _Refs(HTMLParser):
    """URLs in attributes, CSS in ``<style>`` and ``style=``, and inline script text."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.urls: list[str] = []
        self.css: list[str] = []
        self.scripts: list[str] = []
        self._in: str | None = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for name, value in attrs:
            if not value:
                continue
            if name in ("src", "href", "poster", "data", "background") and tag != "base":
                self.urls.append(value)
            elif name in ("srcset", "imagesrcset"):
                self.urls.extend(part.split()[0] for part in value.split(",") if part.split())
            elif name == "style":
                self.css.append(value)
        self._in = tag if tag in ("script", "style") else None

    def handle_endtag(self, tag: str) -> None:
        self._in = None

    def handle_data(self, data: str) -> None:
        if self._in == "style":
            self.css.append(data)
        elif self._in == "script":
            self.scripts.append(data)


def _local(url: str) -> str | None:
    """The path part of a URL that names a file of this site (None for other sites)."""
    url = url.strip()
    if not url or url.startswith(("#", "//", "data:", "javascript:", "mailto:", "blob:")):
        return None
    try:
        parts = urlsplit(url)
    except ValueError:
        return None
    if parts.scheme or parts.netloc:
        return None
    return unquote(parts.path.replace("\\", "/")) or None


def references(file: Path) -> tuple[list[str], list[str]]:
    """(URLs that must exist, strings that may name files) found in one file of a demo."""
    name = file.name.lower()
    try:
        text = file.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return [], []
    if name.endswith(_HTML):
        refs = _Refs()
        refs.feed(text)
        refs.close()
        css = [m.group(2) or m.group(4) for c in refs.css for m in _CSS_URL.finditer(c)]
        maybe = [m.group(2) for s in refs.scripts for m in _JS_STRING.finditer(s)]
        return refs.urls + css, maybe
    if name.endswith(_CSS):
        return [m.group(2) or m.group(4) for m in _CSS_URL.finditer(text)], []
    if name.endswith(".mtl"):
        return [], _MTL_MAP.findall(text)
    if name.endswith(_JS):
        return [], [m.group(2) for m in _JS_STRING.finditer(text)]
    return [], []


class PageFiles:
    """Plans the copies an iframed local page needs, through the importer's asset lookup.

    ``resolve(site_path)`` returns the source file of a site path such as
    ``downloads/threejs_ex/three.min.js`` (or None when the site lacks it) and plans its
    copy; ``inside(site_path)`` says whether the path is one the import copies at all.
    """

    def __init__(
        self,
        resolve: Callable[[str], Path | None],
        inside: Callable[[str], bool],
    ) -> None:
        self.resolve = resolve
        self.inside = inside
        self.seen: set[str] = set()

    def follow(self, site_path: str, problems: list[str]) -> int:
        """Copy what the page at ``site_path`` loads, recursively; returns files added.
        Problems (missing files, references leaving the copied folders) go to ``problems``.

        A URL in a file resolves against that file (HTML, CSS, an ES module's imports); a
        string in a script may also be a URL the page's document resolves (a loader's
        `load('model.obj')`), so both are tried, and only files that exist are taken."""
        added = 0
        queue = [(site_path, posixpath.dirname(site_path))]  # (file, its document's folder)
        self.seen.add(site_path)
        while queue:
            current, document = queue.pop(0)
            source = self.resolve(current)
            if source is None:
                continue
            base = posixpath.dirname(current)
            if current.lower().endswith(_HTML):
                document = base
            required, optional = references(source)
            for url in required:
                target = self._target(base, url)
                if target is None or target in self.seen:
                    continue
                self.seen.add(target)
                if not self.inside(target):
                    problems.append(f"{current} loads {url}, outside images/, downloads/, static/")
                elif self.resolve(target) is None:
                    problems.append(f"{current} loads {url}, which is not in the site")
                else:
                    added += 1
                    queue.append((target, document))
            for text in optional:  # a string in a script: taken only when such a file exists
                for where in dict.fromkeys((base, document)):
                    target = self._target(where, text)
                    if (
                        target is not None
                        and target not in self.seen
                        and self.inside(target)
                        and self.resolve(target) is not None
                    ):
                        self.seen.add(target)
                        added += 1
                        queue.append((target, document))
            if len(self.seen) > MAX_FILES:
                problems.append(f"more than {MAX_FILES} files under {site_path}: stopped there")
                break
        return added

    @staticmethod
    def _target(base: str, url: str) -> str | None:
        path = _local(url)
        if path is None:
            return None
        joined = path.lstrip("/") if path.startswith("/") else posixpath.join(base, path)
        normal = posixpath.normpath(joined)
        if normal.startswith("..") or normal in (".", ""):
            return "../" + normal  # leaves the site: reported by the caller
        return normal
