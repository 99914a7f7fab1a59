"""The blog: dated posts in ``blog.dir`` (``blog/``), listed newest first, outside the pages.

Posts are ordinary pages of the site (so they are rendered, link-checked and searched like
every page) kept in one top-level section that sorts last in the menu. Their order there is
their date, newest first, so previous/next on a post goes to the next newer/older post. The
section's own page is the first page of the index; the other index pages, one page per tag,
the yearly archive and the Atom feed (``feed.xml``, when ``base_url`` is set) are made from
the rendered site by :meth:`BlogIntegration.site_files`. A post without ``date:`` is an
error naming its file; a date that does not parse is one naming its line (content.py).
"""

from __future__ import annotations

import hashlib
import re
from dataclasses import replace
from html import escape
from pathlib import PurePosixPath
from urllib.parse import quote

from sitegen.config import Config
from sitegen.errors import Diagnostics
from sitegen.integrations import Built, Integration
from sitegen.nav import Node, PageInput
from sitegen.post_dates import day
from sitegen.slugs import slugify, unique

LAST = 10**9 + 1  # sorts after every page without a weight: the blog is the menu's last entry
LABELS = {
    "en": {
        "blog": "Blog",
        "tags": "Tags",
        "archive": "Archive",
        "feed": "Atom feed",
        "newer": "Newer posts",
        "older": "Older posts",
        "page": "page {n}",
        "tagged": "Posts tagged “{tag}”",
        "posts": "{n} posts",
    },
    "zh-TW": {
        "blog": "網誌",
        "tags": "標籤",
        "archive": "年度彙整",
        "feed": "Atom 訂閱",
        "newer": "較新的文章",
        "older": "較舊的文章",
        "page": "第 {n} 頁",
        "tagged": "標籤「{tag}」的文章",
        "posts": "{n} 篇文章",
    },
}


def _href(from_url: str, to_url: str) -> str:
    from sitegen.links import relative, url_quote

    return url_quote(relative(from_url, to_url))


SUMMARY_CHARS = 280  # a post without ``summary:`` shows the start of its text
_FENCE = re.compile(r"^\s*(`{3,}|~{3,})")
_SKIP = ("#", ":::", "!!!", "???", "===", "|", "<", "{:", "[^", "Note:", "Notes:", "---")
_MARKER = re.compile(r"^(?:[-*+]|\d+[.)]|>)\s+")


def excerpt(markdown: str) -> str:
    """The start of a post's text as a reader reads it, for the blog's lists and its feed:
    paragraphs, list items and quotes with their inline markup undone; headings, code, tables,
    HTML and directives left out. Cut at a space near :data:`SUMMARY_CHARS` (CJK text, which
    has no spaces, at the limit), with an ellipsis."""
    from sitegen.page_text import plain_title

    words, fenced = [], False
    for line in markdown.splitlines():
        if _FENCE.match(line):
            fenced = not fenced
            continue
        text = line.strip()
        if fenced or not text or text.startswith(_SKIP):
            continue
        words.append(plain_title(_MARKER.sub("", text)))
        if sum(len(w) for w in words) > SUMMARY_CHARS:
            break
    text = re.sub(r"<[^>]*>", "", " ".join(words))
    text = " ".join(text.split())
    if len(text) <= SUMMARY_CHARS:
        return text
    cut = text[:SUMMARY_CHARS]
    space = cut.rfind(" ")
    return (cut[:space] if space > SUMMARY_CHARS // 2 else cut).rstrip(" ,.;:，。、；：") + "…"


class BlogIntegration(Integration):
    def __init__(self, config: Config):
        self.config = config
        self.dir = PurePosixPath(config.blog.dir)
        self.labels = LABELS.get(config.language, LABELS["en"])
        self.title = config.blog.title or self.labels["blog"]
        self.size = config.blog.page_size
        self.meta: dict[PurePosixPath, dict] = {}  # post -> its front matter, newest first
        self.tag_slugs: dict[str, str] = {}

    # -- before the tree: find, check and order the posts ------------------------------------

    def _file(self, rel: PurePosixPath) -> str:
        if self.config.source_file is None:
            return str(rel)
        return f"{self.config.content_dir.as_posix()}/{rel}"

    def adjust(self, inputs: list[PageInput], diags: Diagnostics) -> list[PageInput]:
        from sitegen.slides import insert_under_title

        mine = [p for p in inputs if p.rel.parent == self.dir and p.body_html is None]
        index = next((p for p in mine if p.is_index), None)
        posts = [p for p in mine if not p.is_index]
        if not posts and index is None:
            return inputs
        dated = []
        for p in posts:
            reported = any(d.field == "date" and d.file == str(p.rel) for d in diags.items)
            if "date" not in p.meta and not reported:
                diags.error(
                    self._file(p.rel), 1, "date", "a blog post needs a date (date: YYYY-MM-DD)"
                )
            elif "date" in p.meta:
                dated.append(p)
            if "weight" in p.meta:
                diags.warning(
                    self._file(p.rel), None, "weight", "ignored: posts are ordered by date"
                )
        dated.sort(key=lambda p: p.rel.name)
        dated.sort(key=lambda p: p.meta["date"], reverse=True)
        taken: set[str] = {"index"}
        for tag in sorted({t for p in dated for t in p.meta.get("tags", ())}):
            self.tag_slugs[tag] = unique(slugify(tag, "tag"), taken)
        changed: dict[int, PageInput] = {}
        for rank, p in enumerate(dated):
            # the lists and the feed show the same words: the author's summary, else an excerpt
            self.meta[p.rel] = {**p.meta, "summary": p.meta.get("summary") or excerpt(p.text)}
            text, first = insert_under_title(p.text, p.body_line, "::: blog post")
            changed[id(p)] = replace(p, text=text, body_line=first, meta={**p.meta, "weight": rank})
        if index is not None:
            meta = {"weight": LAST, "title": self.title, **index.meta, "_children": False}
            text = index.text.rstrip() + "\n\n::: blog index\n"
            changed[id(index)] = replace(index, text=text, meta=meta)
        out = [changed.get(id(p), p) for p in inputs]
        if index is None:
            text = "::: blog index\n"
            out.append(
                PageInput(
                    self.dir / "index.md",
                    {"title": self.title, "weight": LAST, "_children": False},
                    text,
                    True,
                    None,
                    "index",
                    digest=hashlib.sha256(text.encode()).hexdigest(),
                )
            )
        return out

    def fingerprint(self) -> str:
        """What the directives' output depends on beyond the tree: dates, tags, summaries."""
        keys = ("date", "tags", "summary")
        data = repr([(str(r), [m.get(k) for k in keys]) for r, m in self.meta.items()])
        return "blog:" + hashlib.sha256(f"{data}{self.size}".encode()).hexdigest()

    # -- in pages: the list on the index, the date and tags on a post ------------------------

    def directives(self) -> dict:
        def blog(arg: str, node: Node) -> str:
            if arg == "post":
                return self._post_meta(node)
            if arg == "index":
                posts = self._posts(node)
                return self._listing(node.url, posts[: self.size], node) + self._pager(
                    node, node.url, 1, self._pages(len(posts))
                )
            raise LookupError(f"unknown blog directive '{arg}' (known: index, post)")

        return {"blog": blog}

    def _posts(self, section: Node) -> list[Node]:
        kids = [c for c in section.children if c.source is not None]
        return [c for c in kids if c.source.rel in self.meta]

    def _pages(self, n: int) -> int:
        return max(1, -(-n // self.size))

    def _tag_url(self, section: Node, tag: str) -> str:
        return f"{section.url.rsplit('/', 1)[0]}/tags/{self.tag_slugs[tag]}.html"

    def _meta_line(self, from_url: str, post: Node, section: Node) -> str:
        meta = self.meta[post.source.rel]
        when = day(meta["date"])
        tags = " ".join(
            f'<a class="tag" rel="tag" href="{_href(from_url, self._tag_url(section, t))}">'
            f"{escape(t)}</a>"
            for t in meta.get("tags", ())
        )
        return f'<time datetime="{when}">{when}</time>' + (f" · {tags}" if tags else "")

    def _post_meta(self, node: Node) -> str:
        if node.parent is None or node.source is None or node.source.rel not in self.meta:
            return ""
        return f'<p class="post-meta">{self._meta_line(node.url, node, node.parent)}</p>'

    def _listing(self, from_url: str, posts: list[Node], section: Node) -> str:
        items = []
        for post in posts:
            summary = self.meta[post.source.rel].get("summary")
            items.append(
                f'<article class="post-summary"><h2><a href="{_href(from_url, post.url)}">'
                f"{escape(post.title)}</a></h2>\n"
                f'<p class="post-meta">{self._meta_line(from_url, post, section)}</p>'
                + (f"\n<p>{escape(summary)}</p>" if summary else "")
                + "</article>"
            )
        return '<div class="blog-list">\n' + "\n".join(items) + "\n</div>\n"

    def _page_url(self, section: Node, n: int) -> str:
        return section.url if n == 1 else f"{section.url.rsplit('/', 1)[0]}/page-{n}.html"

    def _pager(self, section: Node, from_url: str, n: int, total: int) -> str:
        base = section.url.rsplit("/", 1)[0]
        links = []
        if n > 1:
            href = _href(from_url, self._page_url(section, n - 1))
            links.append(f'<a class="newer" rel="prev" href="{href}">« {self.labels["newer"]}</a>')
        if n < total:
            href = _href(from_url, self._page_url(section, n + 1))
            links.append(f'<a class="older" rel="next" href="{href}">{self.labels["older"]} »</a>')
        links.append(
            f'<a href="{_href(from_url, base + "/archive.html")}">{self.labels["archive"]}</a>'
        )
        if self.tag_slugs:
            links.append(
                f'<a href="{_href(from_url, base + "/tags/index.html")}">{self.labels["tags"]}</a>'
            )
        if self.config.base_url:
            links.append(
                f'<a href="{_href(from_url, "feed.xml")}" type="application/atom+xml">'
                f"{self.labels['feed']}</a>"
            )
        return '<p class="blog-pager">' + " · ".join(links) + "</p>\n"

    # -- after the pages: the other index pages, tags, archive, feed -------------------------

    def site_files(self, built: Built, diags: Diagnostics) -> dict[str, bytes]:
        section = built.site.by_dir.get(self.dir)
        if section is None or not self.meta:
            return {}
        # only here: the feed's XML escaping imports urllib.request (~50 ms) a site without a
        # blog need not pay for
        from sitegen.blog_feed import atom_feed
        from sitegen.pages import render_page, root_prefix

        posts = self._posts(section)
        base = section.url.rsplit("/", 1)[0]
        home = {"title": built.site.root.title, "url": built.site.root.url}
        crumb = {"title": section.title, "url": section.url}
        made: dict[str, tuple[str, str]] = {}  # url -> (title, body)
        total = self._pages(len(posts))
        for n in range(2, total + 1):
            url = self._page_url(section, n)
            chunk = posts[(n - 1) * self.size : n * self.size]
            body = self._listing(url, chunk, section) + self._pager(section, url, n, total)
            made[url] = (f"{section.title} · {self.labels['page'].format(n=n)}", body)
        tag_items = []
        for tag, slug in self.tag_slugs.items():
            url = self._tag_url(section, tag)
            tagged = [p for p in posts if tag in self.meta[p.source.rel].get("tags", ())]
            made[url] = (self.labels["tagged"].format(tag=tag), self._listing(url, tagged, section))
            count = self.labels["posts"].format(n=len(tagged))
            tag_items.append(
                f'<li><a class="tag" rel="tag" href="{quote(slug)}.html">{escape(tag)}</a>'
                f" ({count})</li>"
            )
        if tag_items:
            made[f"{base}/tags/index.html"] = (
                self.labels["tags"],
                '<ul class="blog-tags">\n' + "\n".join(tag_items) + "\n</ul>\n",
            )
        years: dict[str, list[Node]] = {}
        for p in posts:
            years.setdefault(self.meta[p.source.rel]["date"][:4], []).append(p)
        url = f"{base}/archive.html"
        parts = [
            f'<h2 id="y{y}">{y}</h2>\n' + self._listing(url, ps, section) for y, ps in years.items()
        ]
        made[url] = (self.labels["archive"], "\n".join(parts))
        out: dict[str, bytes] = {}
        for url, (title, body) in made.items():
            context = {
                **built.base,
                "root": root_prefix(url),
                "page": {
                    "title": title,
                    "url": url,
                    "body": body,
                    "toc": [],
                    "breadcrumbs": [home, crumb],
                    "prev": None,
                    "next": None,
                    "children": [],
                    "is_home": False,
                },
            }
            # a stand-in section at the file's own depth: the menu's links are relative to it
            here = Node(title, url, None, section.rel_dir, True, parent=section)
            out[url] = render_page(built.theme, built.menus, here, context)
        if self.config.base_url:
            entries = [(p, self.meta[p.source.rel], built.renders[p.url].text) for p in posts]
            out["feed.xml"] = atom_feed(self.config, section, entries, self.title)
        return out
