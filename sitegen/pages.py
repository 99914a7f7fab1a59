"""Nodes -> page outputs: template contexts, the special pages, and the site-wide files.

A page is re-rendered only when the hash of its template context changes; the context is
plain JSON-able data, so the hash covers everything the page shows (its body, menu,
breadcrumb, neighbours' titles) and nothing else.
"""

from __future__ import annotations

import hashlib
import os
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

from markupsafe import Markup

from sitegen.nav import Node, Site, full_tree, menu_for, menu_owner

if TYPE_CHECKING:  # integrations import this module for root_prefix: keep Jinja2 out
    from sitegen.config import Config
    from sitegen.theme import Theme

# Every page: the name of the generated special pages, kept out of the content namespace.


@dataclass
class PageBody:
    """A page's converted body, table of contents and plain text."""

    html: str
    toc: list[dict]
    text: str


def build_date() -> str | None:
    """Only with SOURCE_DATE_EPOCH: otherwise two builds of the same input must be identical."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if not epoch or not epoch.strip().isdigit():
        return None
    return time.strftime("%Y-%m-%d", time.gmtime(int(epoch)))


def root_prefix(url: str) -> str:
    return "../" * url.count("/")


def _link(n: Node | None) -> dict | None:
    return None if n is None else {"title": n.title, "url": n.url}


def site_context(config: Config, strings: dict) -> dict:
    return {
        "site": {
            "title": config.title,
            "language": config.language,
            "description": config.description,
            "author": config.author,
            "base_url": config.base_url or "",
        },
        "t": strings,
        "build_date": build_date(),
    }


def page_context(site: Site, node: Node, body: PageBody, base: dict) -> dict:
    order = site.order
    prev_node = order[node.index - 1] if node.index > 0 else None
    next_node = order[node.index + 1] if node.index + 1 < len(order) else None
    crumbs = [_link(a) for a in node.ancestors()]
    listed = node.source is None or node.source.meta.get("_children", True)  # blog: its own list
    children = (
        [_link(c) for c in node.children]
        if node.is_section and node.parent is not None and listed
        else []
    )
    return {
        **base,
        "root": root_prefix(node.url),
        "page": {
            "title": node.title,
            "url": node.url,
            "body": body.html,
            "toc": body.toc,
            "breadcrumbs": crumbs,
            "prev": _link(prev_node),
            "next": _link(next_node),
            "children": children,
            "is_home": node.parent is None,
        },
    }


class MenuSignatures:
    """What each page's menu looks like, as a short string, without building 1000 menus.

    A page's menu is its parent's open branch with the page marked current (sections also
    open their own children), so pages in one folder share one signature plus their URL.
    """

    def __init__(self, site: Site):
        self.site = site
        self._by_node: dict[int, str] = {}

    def _of(self, node: Node) -> str:
        sig = self._by_node.get(id(node))
        if sig is None:
            sig = hashlib.sha256(repr(menu_for(self.site, node)).encode()).hexdigest()
            self._by_node[id(node)] = sig
        return sig

    def __call__(self, node: Node) -> str:
        if node.is_section or node.parent is None:
            return self._of(node)
        return f"{self._of(node.parent)}|{node.url}"


def context_hash(context: dict, theme_digest: str, menu_signature: str) -> str:
    """Hash of everything a page shows. ``repr`` is exact for these plain dicts, lists and
    strings (always built in the same key order) and several times faster than JSON."""
    text = f"{theme_digest}\0{menu_signature}\0{context!r}"
    return hashlib.sha256(text.encode()).hexdigest()


class Menus:
    """Menu HTML for each page, from the theme's ``menu.html``, rendered once per folder.

    The pages of one folder show the same menu but for the mark on their own entry, so the
    folder's menu is rendered once with nothing marked and each page's entry, rendered alone
    by the ``item`` macro, is swapped for its marked form: a string replace instead of a
    recursive macro per page. A theme whose menu does not contain each entry exactly once as
    ``item()`` renders it gets the whole menu rendered per page (same output, slower).
    """

    def __init__(self, theme: Theme, site: Site):
        self.site = site
        self.template = theme.env.get_template("menu.html")
        self._macros: dict[str, object] = {}
        self._shared: dict[int, str] = {}

    def _module(self, root: str):
        module = self._macros.get(root)
        if module is None:
            module = self._macros[root] = self.template.make_module({"root": root})
        return module

    def html(self, node: Node | None) -> Markup:
        """The menu of ``node``; None: the site root's menu with nothing marked."""
        if node is None:
            return self._module("").tree(menu_for(self.site, self.site.root, mark_current=False))
        macros = self._module(root_prefix(node.url))
        owner = menu_owner(node)
        if owner is None:
            return macros.tree(menu_for(self.site, node))
        shared = self._shared.get(id(owner))
        if shared is None:
            shared = str(macros.tree(menu_for(self.site, owner, mark_current=False)))
            self._shared[id(owner)] = shared
        entry = {"title": node.title, "url": node.url, "has_children": False, "children": []}
        plain = str(macros.item({**entry, "current": False, "open": False}, False))
        if shared.count(plain) != 1:
            return macros.tree(menu_for(self.site, node))
        marked = str(macros.item({**entry, "current": True, "open": True}, True))
        return Markup(shared.replace(plain, marked))


def render_page(theme: Theme, menus: Menus, node: Node, context: dict) -> bytes:
    ctx = dict(context, menu_html=menus.html(node))
    ctx["page"] = dict(ctx["page"], body=Markup(ctx["page"]["body"]))
    return theme.render("page.html", ctx).encode()


def special_pages(theme: Theme, site: Site, base: dict, menus: Menus) -> dict[str, bytes]:
    """Site Map (the full tree), the search page and the 404 page, all at the site root."""
    common = {**base, "root": "", "menu_html": menus.html(None), "page": {"title": "", "url": ""}}
    return {
        "sitemap.html": theme.render(
            "sitemap.html", {**common, "full_tree": full_tree(site)}
        ).encode(),
        "search.html": theme.render("search.html", common).encode(),
        "404.html": theme.render("404.html", common).encode(),
        # the whole tree, so the menu can expand any section in place (the reader's theme)
        "assets/nav.js": theme.render("nav.js", {"full_tree": full_tree(site)}).encode(),
    }


def sitemap_xml(site: Site, base_url: str) -> bytes:
    from urllib.parse import quote

    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        '<urlset xmlns="http://www.sitemaps.org/schemas/sitemap/0.9">',
    ]
    date = build_date()
    for n in site.order:
        loc = base_url + quote(n.url, safe="/-._~")
        if n.url == "index.html":
            loc = base_url
        lastmod = f"<lastmod>{date}</lastmod>" if date else ""
        lines.append(f"  <url><loc>{loc}</loc>{lastmod}</url>")
    lines.append("</urlset>")
    return ("\n".join(lines) + "\n").encode()
