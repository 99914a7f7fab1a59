"""``sitegen build``: the pipeline, with I/O at the edges.

config -> scan files -> integrations (rosters, clips) -> navigation -> Markdown (cached by
source hash) -> links and directives -> page contexts (rendered only when their hash
changes) -> site-wide files -> check -> publish atomically -> save the cache.
"""

from __future__ import annotations

import hashlib
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from sitegen import __version__
from sitegen.cache import Cache, Fragments, State
from sitegen.config import Config, load_config
from sitegen.content import SourcePage, scan
from sitegen.errors import BuildError, Diagnostic, Diagnostics
from sitegen.i18n import strings
from sitegen.integrations import Integration, make_integrations
from sitegen.links import LinkTargets, expand_directives, rewrite_links
from sitegen.nav import PageInput, build_site
from sitegen.output import OutFile, from_bytes, publish
from sitegen.output import intact as output_intact
from sitegen.output import unchanged as output_unchanged
from sitegen.pages import (
    MenuSignatures,
    PageBody,
    context_hash,
    page_context,
    render_page,
    search_entries,
    site_context,
    sitemap_xml,
    special_pages,
)
from sitegen.search import search_records, search_script
from sitegen.theme import Theme


@dataclass
class BuildOptions:
    source: Path = Path(".")
    output: Path | None = None
    strict: bool = False
    clean: bool = False
    cache_dir: Path | None = None
    log: Callable[[str], None] = lambda line: print(line, file=sys.stderr)
    is_tty: bool = False


@dataclass
class BuildReport:
    output: Path
    pages: int = 0
    markdown_rendered: int = 0
    pages_rendered: int = 0
    changed: list[str] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    seconds: float = 0.0
    up_to_date: bool = False


def resolve_paths(opts: BuildOptions) -> tuple[Config, Path, Path, Path]:
    source = opts.source.resolve()
    if not source.is_dir():
        raise BuildError(
            "bad source", [Diagnostic(str(opts.source), None, "--source", "is not a folder")]
        )
    config = load_config(source)
    project = config.source_file is not None
    content = (source / config.content_dir) if project else source
    if not content.is_dir():
        raise BuildError(
            "no content", [Diagnostic(str(content), None, "content_dir", "folder not found")]
        )
    output = (opts.output or (source / config.output_dir if project else Path("site"))).resolve()
    if output == source or output == content or content.is_relative_to(output):
        raise BuildError(
            "bad output",
            [
                Diagnostic(
                    str(output), None, "--output", "must not be the source folder or contain it"
                )
            ],
        )
    cache_dir = opts.cache_dir or (
        source / ".sitegen-cache" if project else output.parent / f".sitegen-cache-{output.name}"
    )
    return config, content, output, cache_dir.resolve()


def to_input(page: SourcePage) -> PageInput:
    return PageInput(
        page.rel,
        page.meta,
        page.text,
        page.is_index,
        page.prefix,
        page.stem,
        body_line=page.body_line,
        digest=page.digest,
    )


def build(opts: BuildOptions) -> BuildReport:
    """Build the site; raise :class:`BuildError` (previous site untouched) on errors."""
    started = time.perf_counter()
    config, content_root, output, cache_dir = resolve_paths(opts)
    report = BuildReport(output=output)
    diags = Diagnostics()
    cache = Cache(cache_dir)
    state = State() if opts.clean else cache.load_state()

    tree = scan(content_root, diags, exclude={output, cache_dir})
    theme = Theme(
        (config.root / config.templates_dir)
        if config.templates_dir
        else (config.root / "templates" if config.source_file else None)
    )
    theme_digest = theme.digest()
    integrations = make_integrations(config, cache_dir, opts)
    fingerprint = _fingerprint(config, tree, theme_digest, integrations)
    if (
        not opts.clean
        and state.fingerprint == fingerprint
        and state.output == str(output)
        and not diags.items
        and output_intact(output, state.manifest)
    ):
        report.up_to_date = True
        report.seconds = time.perf_counter() - started
        return report

    t = strings(config.language)
    inputs = [to_input(p) for p in tree.pages]
    files: dict[str, OutFile] = {}
    handlers: dict = {}
    for integ in integrations:
        integ.prepare(diags, state)
        inputs.extend(integ.pages(t))
        handlers.update(integ.directives())
    _check_collisions(inputs, diags)
    site = build_site(inputs, home_title=t["home"])
    frag = Fragments() if opts.clean else cache.load_fragments()
    renders = _render_markdown(site, frag, report)
    bodies: dict[str, PageBody] = {}
    assets = {a.rel for a in tree.assets}
    targets = LinkTargets.build(site, assets, {url: set(r.ids) for url, r in renders.items()})

    base = site_context(config, t)
    new_pages: dict[str, tuple[str, str]] = {}
    menu_signature = MenuSignatures(site)
    for node in site.order:
        src = node.source
        file = str(src.rel) if src else node.url
        rendered = renders[node.url]
        body = rendered.html
        if src is not None and src.body_html is None:
            # links first: directive output is generated with final relative URLs already
            body = rewrite_links(
                body, node, targets, diags, f"{content_root.name}/{file}", src.text, src.body_line
            )
            body = expand_directives(
                body,
                node,
                handlers,
                diags,
                f"{content_root.name}/{file}",
                rendered.directives,
                src.body_line,
            )
        bodies[node.url] = PageBody(body, rendered.toc, rendered.text)
        ctx = page_context(site, node, bodies[node.url], base)
        key = context_hash(ctx, theme_digest, menu_signature(node))
        old = frag.pages.get(node.url)
        if old and old[0] == key and output_unchanged(output, node.url, state.manifest, old[1]):
            files[node.url] = OutFile(old[1], source=output / node.url)
        else:
            files[node.url] = from_bytes(render_page(theme, site, node, ctx))
            report.pages_rendered += 1
        new_pages[node.url] = (key, files[node.url].digest)
    report.pages = len(site.order)

    for rel, data in special_pages(theme, site, base).items():
        files[rel] = from_bytes(data)
    for rel, data in theme.assets().items():
        files[rel] = from_bytes(data)
    files["assets/search-index.js"] = from_bytes(
        search_script(search_records(search_entries(site, bodies)))
    )
    files[".nojekyll"] = from_bytes(b"")
    if config.base_url:
        files["sitemap.xml"] = from_bytes(sitemap_xml(site, config.base_url))
    for asset in tree.assets:
        rel = str(asset.rel)
        if rel in files:
            diags.error(
                f"{content_root.name}/{rel}", None, "", f"clashes with a generated file '{rel}'"
            )
            continue
        files[rel] = OutFile(asset.digest, source=asset.path)
    for integ in integrations:
        for rel, f in integ.files().items():
            files[rel] = f
        report.notes.extend(integ.notes(state))

    report.diagnostics = sorted(diags.items, key=lambda d: (d.file, d.line or 0, d.message))
    if diags.errors or (opts.strict and diags.warnings):
        why = "errors" if diags.errors else "warnings (--strict)"
        raise BuildError(
            f"build failed with {why}; the previous site was left as it was", report.diagnostics
        )

    manifest, report.changed = publish(output, files, state.manifest)
    new_state = State(fingerprint if not diags.warnings else "", str(output), manifest)
    for integ in integrations:
        integ.save(new_state)
    cache.save_state(new_state)
    frag.pages = new_pages
    cache.save_fragments(frag)
    report.seconds = time.perf_counter() - started
    return report


def _render_markdown(site, frag: Fragments, report: BuildReport):
    """Markdown -> fragments, reusing the cache for every source whose hash is unchanged."""
    from sitegen.markdown_render import RENDER_VERSION, MarkdownRenderer, Rendered, plain_text

    renderer: MarkdownRenderer | None = None
    renders: dict[str, Rendered] = {}
    used: dict[str, Rendered] = {}
    for node in site.order:
        src = node.source
        if src is None:  # a folder without index.md: the template lists its children
            renders[node.url] = Rendered("", [], [], "")
            continue
        if src.body_html is not None:
            renders[node.url] = Rendered(
                src.body_html, src.toc or [], _ids(src.body_html), plain_text(src.body_html)
            )
            continue
        key = hashlib.sha256(
            f"{RENDER_VERSION}\0{node.strip_first_heading}\0{src.text}".encode()
        ).hexdigest()
        cached = frag.markdown.get(key)
        if cached is None:
            renderer = renderer or MarkdownRenderer()
            cached = renderer.render(src.text, node.strip_first_heading)
            report.markdown_rendered += 1
        renders[node.url] = used[key] = cached
    frag.markdown = used
    return renders


def _ids(html: str) -> list[str]:
    import re

    return re.findall(r'\sid="([^"]+)"', html)


def _check_collisions(inputs: list[PageInput], diags: Diagnostics) -> None:
    seen: dict[PurePosixPath, PageInput] = {}
    for p in inputs:
        if p.rel in seen:
            diags.error(
                str(p.rel), None, "", "a generated page has the same path as a content page"
            )
        seen[p.rel] = p


def _fingerprint(config: Config, tree, theme_digest: str, integrations: list[Integration]) -> str:
    h = hashlib.sha256()
    h.update(f"{__version__}\0{config!r}\0{theme_digest}\0{_code_digest()}\0".encode())
    for p in tree.pages:
        h.update(f"p\0{p.rel}\0{p.digest}\0".encode())
    for a in tree.assets:
        h.update(f"a\0{a.rel}\0{a.digest}\0".encode())
    for integ in integrations:
        h.update(integ.fingerprint().encode())
    import os

    h.update(os.environ.get("SOURCE_DATE_EPOCH", "").encode())
    return h.hexdigest()


def _code_digest() -> str:
    """Our own code and the Markdown stack are inputs too: an upgrade must rebuild."""
    import markdown
    import pygments

    h = hashlib.sha256(f"{markdown.__version__}\0{pygments.__version__}".encode())
    for f in sorted(Path(__file__).parent.glob("*.py")):
        h.update(f.read_bytes())
    return h.hexdigest()
