"""URLs in cmsimde content: uploaded files, embedded images and links between pages.

cmsimde serves uploads from the site root (``/images/x.png``, ``/downloads/x.pdf``, its own
``/static/``) and pages as ``/get_page/TITLE`` (dynamic site) or ``TITLE.html`` (static site
in ``content/``). In sitegen a page links to files relative to itself and to other pages by
their ``.md`` source, which the builder turns into page URLs; so every such URL is rewritten
here, and the files it names are planned for copying (or reported missing, naming the link).

A URL that does not parse (``http://user:pw@[proxy_ipv6_address]port``) is kept exactly as
written with a warning, never a traceback; ``//host/...`` becomes ``https://host/...`` so
the imported site works from ``file://``.
"""

from __future__ import annotations

import base64
import binascii
import hashlib
import posixpath
import re
from collections.abc import Callable
from pathlib import Path, PurePosixPath
from typing import Protocol
from urllib.parse import parse_qs, unquote, unquote_to_bytes, urlsplit

from sitegen.importers.htmltree import Element
from sitegen.importers.local_pages import PageFiles
from sitegen.links import external_problem

Warn = Callable[[str, int], None]


class PageLike(Protocol):
    """What link resolution needs of a page: its exact title and its .md path."""

    title: str
    rel: PurePosixPath


_ASSET = re.compile(r"^(?:\.{1,2}/)*/?(images|downloads|static)/(.+)$")
_FRAMES = ("iframe", "frame", "object", "embed")  # elements that show a page inside a page
_PAGES = (".html", ".htm", ".xhtml")
_GET_PAGE = re.compile(r"^/get_page/([^/]+)(?:/\d+)?/?$")
_STATIC_PAGE = re.compile(r"^(?:\.{1,2}/)*/?(?:content/)?([^/]+)\.html?$")
_MIME_EXT = {
    "image/png": "png",
    "image/jpeg": "jpg",
    "image/jpg": "jpg",
    "image/pjpeg": "jpg",
    "image/gif": "gif",
    "image/svg+xml": "svg",
    "image/webp": "webp",
    "image/bmp": "bmp",
    "image/x-icon": "ico",
    "image/vnd.microsoft.icon": "ico",
    "image/avif": "avif",
    "image/tiff": "tif",
}


def relative_to_page(page_rel: PurePosixPath, target: str) -> str:
    """Path from the folder of ``page_rel`` to ``target`` (both relative to the content root)."""
    return posixpath.relpath(target, str(page_rel.parent) or ".")


class Assets:
    """Files referenced under /images, /downloads and /static, and images decoded from data:
    URIs."""

    KINDS = ("images", "downloads", "static")

    def __init__(self, bases: list[Path]) -> None:
        self.bases = bases
        self.copies: dict[str, Path] = {}  # DEST-relative path -> source file
        self.extracted: dict[str, bytes] = {}  # DEST-relative path -> decoded image
        self.missing: set[str] = set()
        self.notes: list[tuple[int, str]] = []  # (line, what was done) for the current page
        self.pages = PageFiles(self.resolve, lambda path: _ASSET.match(path) is not None)

    def find(self, kind: str, sub: str) -> Path | None:
        """The file for ``/kind/sub``; falls back to a case-insensitive match (cmsimde ran on
        Windows)."""
        for base in self.bases:
            folder = base / kind
            exact = folder / sub
            if exact.is_file():
                return exact
            parent = exact.parent
            if parent.is_dir():
                lowered = exact.name.lower()
                for entry in sorted(parent.iterdir()):
                    if entry.name.lower() == lowered and entry.is_file():
                        return entry
        return None

    def link(
        self,
        page_rel: PurePosixPath,
        kind: str,
        sub: str,
        warn: Warn,
        line: int,
        missing: list[str],
    ) -> str | None:
        """Plan the copy of ``/kind/sub`` and return its path relative to the page."""
        sub = posixpath.normpath(sub)
        if sub.startswith("../") or sub in ("..", ".") or sub.startswith("/"):
            warn(f"unsafe path /{kind}/{sub} left as is", line)
            return None
        found = self.find(kind, sub)
        if found is not None:
            sub = (
                posixpath.join(posixpath.dirname(sub), found.name)
                if posixpath.dirname(sub)
                else found.name
            )
            self.copies[f"{kind}/{sub}"] = found
        else:
            self.missing.add(f"{kind}/{sub}")
            missing.append(f"{kind}/{sub}")
        return relative_to_page(page_rel, f"{kind}/{sub}")

    def resolve(self, site_path: str) -> Path | None:
        """The file for a site path (``downloads/demo/x.js``), its copy planned under that
        path as written; None when the site lacks it or the path is not an upload's."""
        m = _ASSET.match(site_path)
        if m is None:
            return None
        found = self.find(m.group(1), m.group(2))
        if found is not None:
            self.copies.setdefault(f"{m.group(1)}/{m.group(2)}", found)
        return found

    def follow_page(self, site_path: str, warn: Warn, line: int) -> None:
        """Copy what an iframed local page loads (:mod:`sitegen.importers.local_pages`)."""
        problems: list[str] = []
        added = self.pages.follow(site_path, problems)
        if added:
            self.notes.append((line, f"iframed page {site_path}: {added} file(s) it loads copied"))
        for problem in problems:
            warn(f"iframed page {problem}", line)

    def data_image(self, page_rel: PurePosixPath, uri: str, el: Element, warn: Warn) -> str | None:
        """Decode a ``data:`` image into ``images/<sha256 prefix>.<ext>``; None if unreadable."""
        head, sep, payload = uri.partition(",")
        if not sep:
            warn("malformed data: image dropped", el.line)
            return None
        params = head[5:].split(";")
        mime = params[0].strip().lower() or "text/plain"
        try:
            if "base64" in (p.strip().lower() for p in params[1:]):
                data = base64.b64decode(re.sub(r"\s+", "", unquote(payload)), validate=True)
            else:
                data = unquote_to_bytes(payload)
        except (binascii.Error, ValueError):
            warn(f"data: image ({mime}) is not valid base64: dropped", el.line)
            return None
        ext = _MIME_EXT.get(mime)
        if ext is None:
            warn(f"data: URI of type {mime} is not an image: dropped", el.line)
            return None
        rel = f"images/{hashlib.sha256(data).hexdigest()[:16]}.{ext}"
        self.extracted[rel] = data
        return relative_to_page(page_rel, rel)

    def site_warnings(self) -> list[str]:
        out = []
        found_any = any((b / k).is_dir() for b in self.bases for k in self.KINDS)
        if self.missing and not found_any:
            out.append(
                f"no images/, downloads/ or static/ folder beside config/ or under content/: "
                f"{len(self.missing)} referenced file(s) not copied"
            )
        unused = []
        for base in self.bases:
            for kind in self.KINDS:
                folder = base / kind
                if folder.is_dir():
                    for file in sorted(p for p in folder.rglob("*") if p.is_file()):
                        rel = f"{kind}/{file.relative_to(folder).as_posix()}"
                        if rel not in self.copies and file not in self.copies.values():
                            unused.append(rel)
        if unused:
            shown = ", ".join(unused[:5]) + (", ..." if len(unused) > 5 else "")
            out.append(
                f"{len(unused)} file(s) in the site not referenced by any page, not copied: {shown}"
            )
        return out


class LinkResolver:
    """Rewrites the URLs of one page: assets relative to it, cmsimde pages to their .md file."""

    def __init__(self, pages: list[PageLike], assets: Assets) -> None:
        self.assets = assets
        self.first = pages[0]
        self.by_title: dict[str, PageLike] = {}
        self.by_static: dict[str, PageLike] = {}
        counts: dict[str, int] = {}
        for page in pages:
            counts[page.title] = counts.get(page.title, 0) + 1
        seen: dict[str, int] = {}
        for page in pages:
            self.by_title.setdefault(page.title, page)
            # cmsimde's generate_pages names duplicates TITLE-1.html, TITLE-2.html, ...
            seen[page.title] = seen.get(page.title, 0) + 1
            name = f"{page.title}-{seen[page.title]}" if counts[page.title] > 1 else page.title
            self.by_static.setdefault(name, page)

    def url(self, page: PageLike, url: str, el: Element, warn: Warn, missing: list[str]) -> str:
        raw = url.strip()
        if not raw or raw.startswith("#"):
            return raw
        problem = external_problem(raw)
        if problem:
            warn(problem, el.line)
            return raw
        parts = urlsplit(raw)
        if raw.startswith("//"):
            return "https:" + raw
        if parts.scheme or parts.netloc:
            return raw
        cut = min((i for i in (raw.find("?"), raw.find("#")) if i >= 0), default=len(raw))
        if "\\" in raw[:cut]:
            # browsers read a backslash in the path of an http(s) URL as "/" (WHATWG URL,
            # "special" schemes): `/downloads/nxopen\block_ui\x.mp4` names
            # /downloads/nxopen/block_ui/x.mp4, so the import reads it so too, and says so
            fixed = raw[:cut].replace("\\", "/") + raw[cut:]
            warn(f"link {raw} has backslashes: read as {fixed}, as browsers do", el.line)
            raw = fixed
            parts = urlsplit(raw)
        suffix = (f"?{parts.query}" if parts.query else "") + (
            f"#{parts.fragment}" if parts.fragment else ""
        )
        path = unquote(parts.path)
        m = _ASSET.match(path)
        if m:
            before = len(missing)
            new = self.assets.link(page.rel, m.group(1), m.group(2), warn, el.line, missing)
            if new is not None and len(missing) > before:
                warn(
                    f"link {raw} names {missing[-1]}, which is not in the site: "
                    f"linked as {new}, where the copy would be",
                    el.line,
                )
            elif new is not None and el.tag in _FRAMES and path.lower().endswith(_PAGES):
                target = posixpath.normpath(
                    posixpath.join(posixpath.dirname(page.rel.as_posix()), new)
                )
                self.assets.follow_page(target, warn, el.line)
            return raw if new is None else new + suffix
        target, named = self._page_for(path, parts.query)
        frag = f"#{parts.fragment}" if parts.fragment else ""
        if target is not None:
            return relative_to_page(page.rel, target.rel.as_posix()) + frag
        if named is not None:
            warn(f"link to unknown cmsimde page {named!r} left as is", el.line)
        elif path.startswith("/"):
            warn(f"link to cmsimde server path {raw} left as is", el.line)
        else:
            warn(f"relative link {raw} left as is", el.line)
        return raw

    def _page_for(self, path: str, query: str) -> tuple[PageLike | None, str | None]:
        """(page, None) if ``path`` names a page; (None, title) if it names an unknown one."""
        if path in ("/", "", "/get_page", "/get_page/") or re.fullmatch(
            r"(?:\.{1,2}/)*/?(?:content/)?index\.html?", path
        ):
            heading = parse_qs(query).get("heading")
            if heading:
                return self.by_title.get(heading[0].strip()), heading[0]
            if not path and query:  # "?x=1" alone is not a page link
                return None, None
            return self.first, None
        m = _GET_PAGE.match(path)
        if m:
            title = m.group(1).strip()
            return self.by_title.get(title), title
        m = _STATIC_PAGE.match(path)
        if m and m.group(1) != "sitemap":
            name = m.group(1)
            page = self.by_static.get(name) or self.by_title.get(name)
            return page, (None if page else name)
        return None, None
