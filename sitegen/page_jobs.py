"""The per-page half of a build: links, directives, context, template, file.

Each page goes through :meth:`PagePhase.run`, which may run in a forked worker
(:mod:`sitegen.workers`): it reads only the shared, read-only build state held here and
returns a small :class:`PageResult`; the rendered page goes straight to a file in the
build's scratch folder, so the site's bytes never pile up in memory.

Work proportional to what changed: :meth:`PagePhase.input_key` hashes what a page's output
depends on *before* links are rewritten (its Markdown fragment, its place in the tree, its
menu, and a digest of everything its links can point at). A page whose input key and output
file are as the last build left them is not touched at all, and the link warnings it had
are reported again from the cache.

Most edits change one page's text and nothing of the tree, so input keys are not even
hashed for every page: :meth:`PagePhase.tree_digest` covers everything an input key takes
from outside the page (tree, theme, link targets, site context), and when it is the last
build's, a page whose own part (:meth:`PagePhase.own_key`) is unchanged keeps its last key.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sitegen.errors import Diagnostic, Diagnostics
from sitegen.links import LinkTargets, expand_directives, rewrite_links
from sitegen.markdown_stage import toc_of
from sitegen.nav import Node, Site
from sitegen.output import Survey
from sitegen.pages import Menus, MenuSignatures, PageBody, context_hash, page_context, render_page
from sitegen.theme import Theme

if TYPE_CHECKING:
    from sitegen.build_inputs import SiteStage


@dataclass
class PageResult:
    """What the build keeps of a page: keys and digest for the cache, its diagnostics."""

    url: str
    input_key: str
    context_key: str
    digest: str
    rendered: bool = False
    diagnostics: list[Diagnostic] = field(default_factory=list)


def links_digest(targets: LinkTargets) -> str:
    """Everything a link or anchor may resolve against: pages, folders, assets, ids."""
    site = targets.site
    h = hashlib.sha256()
    for rel, node in sorted(site.by_source.items(), key=lambda kv: str(kv[0])):
        h.update(f"s\0{rel}\0{node.url}\0".encode())
    for rel, node in sorted(site.by_dir.items(), key=lambda kv: str(kv[0])):
        h.update(f"d\0{rel}\0{node.url}\0".encode())
    for asset in sorted(str(a) for a in targets.assets):
        h.update(f"a\0{asset}\0".encode())
    for url in sorted(targets.ids):
        h.update(f"i\0{url}\0{sorted(targets.ids[url])!r}\0".encode())
    return h.hexdigest()


@dataclass
class PagePhase:
    """The read-only state every page job needs (forked workers inherit it as is)."""

    site: Site
    renders: Mapping[str, Any]  # url -> markdown_render.Rendered (read on demand)
    sources: dict[str, str]  # url -> key of the page's source (Markdown hash) for input keys
    tocs: dict[str, Any]  # url -> the page's table of contents (markdown_stage.toc_of)
    targets: LinkTargets
    handlers: dict
    theme: Theme
    theme_digest: str
    base: dict
    content_name: str
    output: Path
    manifest: dict[str, list]
    found: Survey  # the output folder as the build found it
    old_pages: dict[str, tuple]
    scratch: Path
    salt: str  # links digest + integrations' fingerprints
    menus: Menus = field(init=False)
    menu_signature: MenuSignatures = field(init=False)

    def __post_init__(self) -> None:
        self.menus = Menus(self.theme, self.site)
        self.theme.env.get_template("page.html")  # compiled once, before workers are forked
        self.menu_signature = MenuSignatures(self.site)

    def input_key(self, node: Node) -> str:
        body = PageBody(self.sources.get(node.url, ""), toc_of(self.tocs[node.url]), "")
        ctx = page_context(self.site, node, body, self.base)
        src = node.source
        where = f"{src.rel}\0{src.body_line}" if src is not None else ""
        return context_hash(
            ctx, f"{self.theme_digest}\0{self.salt}\0{where}", self.menu_signature(node)
        )

    def own_key(self, node: Node) -> str:
        """The part of :meth:`input_key` that comes from the page alone: its source key and
        table of contents. A Markdown page's table of contents is made from its source, so
        its source key says it all; a generated page's contents are hashed with it."""
        source = self.sources.get(node.url, "")
        if node.url not in self.renders.held:
            return source
        own = f"{source}\0{toc_of(self.tocs[node.url])!r}"
        return hashlib.sha256(own.encode()).hexdigest()

    def tree_digest(self) -> str:
        """Everything :meth:`input_key` reads besides :meth:`own_key`: the theme, the salt,
        the site context and, for every node in document order, what a page context, a menu
        or a menu signature takes from it. Equal digests and an equal own key: equal input
        keys."""
        rows = []
        for n in self.site.order:
            src = n.source
            parent = n.parent.index if n.parent is not None else -1
            where = (str(src.rel), src.body_line, src.meta.get("_children", True)) if src else ()
            rows.append((n.url, n.title, n.is_section, parent, n.strip_first_heading, where))
        text = f"{self.theme_digest}\0{self.salt}\0{self.base!r}\0{rows!r}"
        return hashlib.sha256(text.encode()).hexdigest()

    def reusable(self, node: Node, key: str) -> PageResult | None:
        """The last build's result for ``node`` if nothing it depends on changed."""
        old = self.old_pages.get(node.url)
        if old is None or old[0] != key or not self._untouched(node.url, old[2]):
            return None
        return PageResult(node.url, old[0], old[1], old[2], False, list(old[3]))

    def _untouched(self, url: str, digest: str) -> bool:
        """The output file is the one the last build wrote (the build's survey of the output
        folder: no stat per page)."""
        return self.found.unchanged(self.manifest, url, digest)

    def run(self, tasks: Sequence[tuple[Node, str | None]]) -> list[PageResult]:
        """Render each (node, input key); in a worker process or in the build's own."""
        return [self.one(node, key) for node, key in tasks]

    def one(self, node: Node, input_key: str | None) -> PageResult:
        """Render ``node``; ``input_key`` None: not made yet (a first build makes them here,
        in the workers, as no page can be reused)."""
        if input_key is None:
            input_key = self.input_key(node)
        diags = Diagnostics()
        src = node.source
        rendered = self.renders[node.url]
        body = rendered.html
        if src is not None and src.body_html is None:
            file = f"{self.content_name}/{src.rel}"
            # links first: directive output is generated with final relative URLs already
            body = rewrite_links(body, node, self.targets, diags, file, src.text, src.body_line)
            body = expand_directives(
                body, node, self.handlers, diags, file, rendered.directives, src.body_line
            )
        ctx = page_context(self.site, node, PageBody(body, rendered.toc, rendered.text), self.base)
        key = context_hash(ctx, self.theme_digest, self.menu_signature(node))
        old = self.old_pages.get(node.url)
        result = PageResult(node.url, input_key, key, "", False, diags.items)
        if old and old[1] == key and self._untouched(node.url, old[2]):
            result.digest = old[2]
            return result
        data = render_page(self.theme, self.menus, node, ctx)
        target = self.scratch / node.url
        try:
            target.write_bytes(data)
        except FileNotFoundError:
            os.makedirs(target.parent, exist_ok=True)
            target.write_bytes(data)
        result.digest = hashlib.sha256(data).hexdigest()
        result.rendered = True
        return result


def render_pages(stage: SiteStage, report: Any) -> tuple[PagePhase, dict[str, Any], dict]:
    """Stage 4: every page whose inputs changed rendered to ``stage.scratch`` (in workers when
    many); the others reused from the output. Returns (the page phase, output files, the
    pages' cache entries)."""
    from sitegen.output import OutFile
    from sitegen.workers import run_chunks

    inp, site, frag, scratch, diags = stage.inp, stage.site, stage.frag, stage.scratch, stage.diags
    phase = PagePhase(
        site=site,
        renders=stage.md.renders,
        sources=stage.md.sources,
        tocs={url: s[1] for url, s in stage.md.summaries.items()},
        targets=stage.targets,
        handlers=stage.handlers,
        theme=inp.theme,
        theme_digest=inp.theme_digest,
        base=stage.base,
        content_name=inp.content_root.name,
        output=inp.output,
        manifest=inp.state.manifest,
        found=inp.found,
        old_pages=frag.pages,
        scratch=scratch,
        salt=stage.salt,
    )
    results: dict[str, PageResult] = {}
    todo: list[tuple] = []
    tree = phase.tree_digest()
    same_tree = tree == frag.tree
    own_keys = {}
    for node in site.order:
        own = own_keys[node.url] = phase.own_key(node)
        old = frag.pages.get(node.url)
        if not frag.pages:  # nothing to reuse: the input keys are made by the page jobs
            todo.append((node, None))
            continue
        if same_tree and old is not None and old[4] == own:
            key = old[0]  # nothing the input key hashes changed: the last build's key
        else:
            key = phase.input_key(node)
        reused = phase.reusable(node, key)
        if reused is None:
            todo.append((node, key))
        else:
            results[node.url] = reused
    for result in run_chunks(todo, phase.run):
        results[result.url] = result
    files: dict[str, Any] = {}
    for node in site.order:
        result = results[node.url]
        diags.extend(result.diagnostics)
        if result.rendered:
            files[node.url] = OutFile(result.digest, source=scratch / node.url, move=True)
            report.pages_rendered += 1
        else:
            files[node.url] = OutFile(result.digest, source=inp.output / node.url)
    report.pages = len(site.order)
    new_pages = {
        url: (r.input_key, r.context_key, r.digest, tuple(r.diagnostics), own_keys[url])
        for url, r in results.items()
    }
    frag.tree = tree
    return phase, files, new_pages
