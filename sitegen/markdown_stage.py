"""The Markdown stage of a build: every page's source -> HTML fragment, ids and contents.

A source whose hash the cache knows is not converted again; the misses are converted in
worker processes when there are many (a cold build), each result going to the fragment
store (:mod:`sitegen.fragment_store`) as soon as it is made, so the site's HTML is never
all in memory. The build keeps only each page's ids, table of contents and directives.
"""

from __future__ import annotations

import hashlib
import pickle
import re
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from sitegen.cache import Fragments
from sitegen.fragment_store import FragmentStore, Renders
from sitegen.nav import Node, Site
from sitegen.page_text import text_key
from sitegen.search import record_json, record_parts
from sitegen.workers import MIN_PARALLEL, run_chunks

_ID = re.compile(r'\sid="([^"]+)"')


@dataclass
class MarkdownStage:
    """What the stage hands on: url -> Rendered (read from the store on demand), url -> key of
    the source (for page input keys), url -> (ids, toc: pickled for a Markdown page, see
    :func:`toc_of`), and how many pages it converted."""

    renders: Renders
    sources: dict[str, str]
    summaries: dict[str, tuple]
    converted: int


def render_markdown(
    site: Site, frag: Fragments, store: FragmentStore, raw_html: str = "keep"
) -> MarkdownStage:
    """Convert what the cache does not hold; ``frag.markdown`` is left holding exactly the
    summaries of the sources the site uses now. ``raw_html="strip"`` cleans each fragment
    (sitegen/html_clean.py; part of the cache key)."""
    clean = raw_html == "strip"
    from sitegen.highlight_cache import BLOCKS
    from sitegen.markdown_render import Rendered, plain_text, render_key

    held: dict[str, Rendered] = {}
    sources: dict[str, str] = {}
    from_store: dict[str, str] = {}
    summaries: dict[str, tuple] = {}
    misses: dict[str, tuple[str, str, bool]] = {}  # key -> (key, text, strip first heading)
    stored = store.keys() if frag.markdown else set()
    code = render_key()
    if clean:  # the cleaning code is part of the key too
        from located.code_keys import code_key

        code += code_key("sitegen.html_clean")
    for node in site.order:
        src = node.source
        if src is None:  # a folder without index.md: the template lists its children
            held[node.url] = Rendered("", [], [], "")
            summaries[node.url] = ([], [])
            continue
        if src.body_html is not None:
            rendered = Rendered(
                src.body_html, src.toc or [], _ID.findall(src.body_html), plain_text(src.body_html)
            )
            held[node.url] = rendered
            summaries[node.url] = (rendered.ids, rendered.toc)
            sources[node.url] = hashlib.sha256(src.body_html.encode()).hexdigest()
            continue
        # the text's own key where the scan made one: an unchanged page's text is not read
        text = src.text_key or text_key(src.text)
        mode = "\0strip-html" if clean else ""
        key = hashlib.sha256(
            f"{code}{mode}\0{node.strip_first_heading}\0{text}".encode()
        ).hexdigest()
        sources[node.url] = from_store[node.url] = key
        if key not in frag.markdown or key not in stored:
            misses.setdefault(key, (key, src.text, node.strip_first_heading))

    def convert(tasks) -> list:
        made = _convert([(text, strip) for _key, text, strip in tasks], clean)
        pairs = ((key, r) for (key, _t, _s), r in zip(tasks, made, strict=True))
        store.put_many(pairs, BLOCKS.take_new())
        # the table of contents pickled: a partial build loads every page's summary but
        # reads the contents of the few pages whose input keys it makes (toc_of)
        return [(r.ids, pickle.dumps(r.toc, 5), r.directives, r.highlights) for r in made]

    tasks = list(misses.values())
    # a cold build's store holds no blocks: asking it for each one would only cost time
    BLOCKS.lookup = store.highlighted if frag.markdown else None
    if len(tasks) >= MIN_PARALLEL:  # workers will be forked: give them what is costly to make
        from sitegen.markdown_render import warm_lexers

        _convert([])  # the renderer is made once, here, and inherited by the workers
        warm_lexers(text for _key, text, _strip in tasks)
    done = run_chunks(tasks, convert, recycle=None)
    for (key, _t, _s), summary in zip(tasks, done, strict=True):
        frag.markdown[key] = summary
    used = {key: frag.markdown[key] for key in from_store.values()}
    for url, key in from_store.items():
        summaries[url] = used[key][:2]
    frag.markdown = used
    return MarkdownStage(Renders(store, from_store, held), sources, summaries, len(tasks))


def toc_of(summary_toc: bytes | list) -> list:
    """A page's table of contents from :attr:`MarkdownStage.summaries` (kept pickled for
    Markdown pages)."""
    return pickle.loads(summary_toc) if isinstance(summary_toc, bytes) else summary_toc


def used_blocks(frag: Fragments) -> set[str]:
    """Keys of the highlighted code blocks the cached pages hold (summaries written by an
    older version have none)."""
    blocks: set[str] = set()
    for summary in frag.markdown.values():
        if len(summary) > 3:
            blocks.update(summary[3])
    return blocks


def search_records(nodes: list[Node], renders: Renders, batch: int = 256) -> Iterator[str]:
    """The search record (JSON) of each of ``nodes``, in order. Text and headings come from
    the small parts the store keeps beside each fragment, read a batch of pages at a time
    (memory stays flat); a page without them (generated pages, a store written by an older
    version) is read whole."""
    for start in range(0, len(nodes), batch):
        chunk = nodes[start : start + batch]
        keys = {
            n.url: renders.keys_by_url[n.url]
            for n in chunk
            if n.url not in renders.held and n.url in renders.keys_by_url
        }
        stored = renders.store.search_parts(sorted(set(keys.values())))
        for n in chunk:
            parts = stored.get(keys.get(n.url, ""))
            if parts is None:
                rendered = renders[n.url]
                parts = record_parts(rendered.text, rendered.toc)
            yield record_json(n.title, n.url, [a.title for a in n.ancestors()], parts)


def _convert(tasks, clean: bool = False) -> list:
    """Convert (Markdown, strip first heading) pairs; one renderer per process, reset per page;
    ``clean``: raw HTML stripped (sitegen/html_clean.py)."""
    global _RENDERER
    from sitegen.markdown_render import MarkdownRenderer

    if _RENDERER is None:
        _RENDERER = MarkdownRenderer()
    return [_RENDERER.render(text, strip, strip_html=clean) for text, strip in tasks]


_RENDERER: Any = None
