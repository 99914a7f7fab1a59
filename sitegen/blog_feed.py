"""The blog's Atom feed (RFC 4287): what a feed reader needs, and nothing that changes between
two builds of the same posts (``updated`` is the newest post's date, not the build time)."""

from __future__ import annotations

from xml.sax.saxutils import escape, quoteattr

from sitegen.config import Config
from sitegen.nav import Node
from sitegen.post_dates import atom_time

SUMMARY_CHARS = 280  # used when an entry has no summary (sitegen.blog.excerpt makes one)


def _abs(base_url: str, url: str) -> str:
    from sitegen.links import url_quote

    return base_url + url_quote(url)


def atom_feed(
    config: Config, section: Node, entries: list[tuple[Node, dict, str]], title: str
) -> bytes:
    """``entries``: (post node, front matter, plain text), newest first."""
    base = config.base_url or ""
    blog = _abs(base, section.url)
    author = config.author or config.title
    updated = atom_time(entries[0][1]["date"]) if entries else "1970-01-01T00:00:00Z"
    lines = [
        '<?xml version="1.0" encoding="utf-8"?>',
        f'<feed xmlns="http://www.w3.org/2005/Atom" xml:lang={quoteattr(config.language)}>',
        f"  <title>{escape(f'{config.title} · {title}')}</title>",
        f"  <id>{escape(blog)}</id>",
        f"  <updated>{updated}</updated>",
        f'  <link rel="alternate" type="text/html" href={quoteattr(blog)}/>',
        f'  <link rel="self" type="application/atom+xml" href={quoteattr(base + "feed.xml")}/>',
        f"  <author><name>{escape(author)}</name></author>",
        "  <generator>sitegen</generator>",
    ]
    for node, meta, text in entries:
        link = _abs(base, node.url)
        summary = meta.get("summary") or _cut(text)
        when = atom_time(meta["date"])
        lines += [
            "  <entry>",
            f"    <title>{escape(node.title)}</title>",
            f"    <id>{escape(link)}</id>",
            f'    <link rel="alternate" type="text/html" href={quoteattr(link)}/>',
            f"    <published>{when}</published>",
            f"    <updated>{when}</updated>",
        ]
        lines += [f"    <category term={quoteattr(t)}/>" for t in meta.get("tags", ())]
        lines += [f"    <summary>{escape(summary)}</summary>", "  </entry>"]
    lines.append("</feed>")
    return ("\n".join(lines) + "\n").encode("utf-8")


def _cut(text: str) -> str:
    if len(text) <= SUMMARY_CHARS:
        return text
    return text[:SUMMARY_CHARS].rsplit(" ", 1)[0] + "…"
