"""``sitegen build``: the pipeline, with I/O at the edges.

config -> scan files -> integrations (rosters, clips) -> navigation -> Markdown (cached by
source hash) -> links and directives -> page contexts (rendered only when their hash
changes) -> site-wide files -> check -> publish atomically -> save the cache.
"""

from __future__ import annotations

import functools
import hashlib
import os
import shutil
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from sitegen import __version__
from sitegen.cache import Cache, Fragments, State
from sitegen.config import Config, load_config
from sitegen.content import SourcePage, scan
from sitegen.errors import BuildError, Diagnostic, Diagnostics
from sitegen.fragment_store import FragmentStore, Renders
from sitegen.i18n import strings
from sitegen.integrations import Built, Integration
from sitegen.links import LinkTargets
from sitegen.nav import PageInput, build_site, full_tree
from sitegen.output import OutFile, from_bytes, output_lock, publish
from sitegen.output import intact as output_intact
from sitegen.output import unchanged as output_unchanged
from sitegen.page_jobs import PagePhase, PageResult, links_digest
from sitegen.pages import (
    site_context,
    sitemap_xml,
    special_pages,
)
from sitegen.plugins import make_integrations
from sitegen.search import write_search_script
from sitegen.theme import Theme
from sitegen.workers import run_chunks


@dataclass
class BuildOptions:
    source: Path = Path(".")
    output: Path | None = None
    strict: bool = False
    clean: bool = False
    cache_dir: Path | None = None
    log: Callable[[str], None] = lambda line: print(line, file=sys.stderr)
    is_tty: bool = False
    retry_failed: bool = False  # render clips whose failure the cache remembers (sims_pages)
    render_clips: bool = True  # False: cached clips only, placeholders for the rest (serve)


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
    """Build the site; raise :class:`BuildError` (previous site untouched) on errors.

    One build per output at a time: the output lock is held for the whole build (cache
    included); a second build raises BuildError at once (sitegen.output.output_lock)."""
    with output_lock(resolve_paths(opts)[2]):
        return _build(opts)


def _build(opts: BuildOptions) -> BuildReport:
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
    _template_cache(theme, cache_dir)
    inputs = [to_input(p) for p in tree.pages]
    files: dict[str, OutFile] = {}
    handlers: dict = {}
    for integ in integrations:
        integ.prepare(diags, state)
        inputs = integ.adjust(inputs, diags)  # slide separators, blog posts' order
        inputs.extend(integ.pages(t))
        handlers.update(integ.directives())
    _check_collisions(inputs, diags)
    site = build_site(inputs, home_title=t["home"])
    frag = Fragments() if opts.clean else cache.load_fragments()
    store = FragmentStore(cache_dir / "fragments.sqlite")
    if opts.clean:
        store.clear()
    renders, sources, summaries = _render_markdown(site, frag, store, report)
    assets = {a.rel for a in tree.assets}
    targets = LinkTargets.build(site, assets, {url: set(s[0]) for url, s in summaries.items()})

    base = site_context(config, t)
    salt = links_digest(targets) + "".join(integ.fingerprint() for integ in integrations)
    scratch = output.parent / f".{output.name}.sitegen-building-{os.getpid()}-pages"
    shutil.rmtree(scratch, ignore_errors=True)
    scratch.mkdir(parents=True)
    try:
        phase = PagePhase(
            site,
            renders,
            sources,
            {url: s[1] for url, s in summaries.items()},
            targets,
            handlers,
            theme,
            theme_digest,
            base,
            content_root.name,
            output,
            state.manifest,
            frag.pages,
            scratch,
            salt,
        )
        results: dict[str, PageResult] = {}
        todo: list[tuple] = []
        for node in site.order:
            key = phase.input_key(node)
            reused = phase.reusable(node, key)
            if reused is None:
                todo.append((node, key))
            else:
                results[node.url] = reused
        for result in run_chunks(todo, phase.run):
            results[result.url] = result
        for node in site.order:
            result = results[node.url]
            diags.extend(result.diagnostics)
            if result.rendered:
                files[node.url] = OutFile(result.digest, source=scratch / node.url, move=True)
                report.pages_rendered += 1
            else:
                files[node.url] = OutFile(result.digest, source=output / node.url)
        new_pages = {
            url: (r.input_key, r.context_key, r.digest, tuple(r.diagnostics))
            for url, r in results.items()
        }
        report.pages = len(site.order)
        built = Built(site, renders, targets, handlers, theme, base, phase.menus, content_root.name)
        for integ in integrations:  # slide decks, blog index pages, tags, archive, feed
            for rel, data in integ.site_files(built, diags).items():
                if rel in files:
                    diags.error(rel, None, "", "a generated file has the same path as a page")
                files[rel] = from_bytes(data)
        reuse = SiteWide(
            output, state.manifest, frag.site_wide, f"{theme_digest}\0{_code_digest()}"
        )
        _finish(
            config,
            tree,
            content_root.name,
            theme,
            site,
            base,
            phase.menus,
            renders,
            files,
            diags,
            reuse,
            scratch,
        )
        report.diagnostics = sorted(diags.items, key=lambda d: (d.file, d.line or 0, d.message))
        if diags.errors or (opts.strict and diags.warnings):
            why = "errors" if diags.errors else "warnings (--strict)"
            raise BuildError(
                f"build failed with {why}; the previous site was left as it was",
                report.diagnostics,
            )
        for integ in integrations:
            for rel, f in integ.files().items():
                files[rel] = f
            report.notes.extend(integ.notes(state))
        manifest, report.changed = publish(output, files, state.manifest)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    new_state = State(fingerprint if not diags.warnings else "", str(output), manifest)
    for integ in integrations:
        integ.save(new_state)
    cache.save_state(new_state)
    frag.pages = new_pages
    frag.site_wide = reuse.new
    cache.save_fragments(frag)
    store.keep_only(set(frag.markdown))
    store.close()
    report.seconds = time.perf_counter() - started
    return report


@dataclass
class SiteWide:
    """Generated files that depend on the whole site (Site Map, search page, theme assets):
    made again only when their inputs' hash changed or the output file was touched, so a
    one-page edit does not re-render a 1000-entry Site Map."""

    output: Path
    manifest: dict[str, list]
    old: dict[str, tuple[str, dict[str, str]]]
    salt: str  # theme digest and library versions
    new: dict[str, tuple[str, dict[str, str]]] = field(default_factory=dict)

    def add(self, files: dict[str, OutFile], name: str, inputs: str, make) -> None:
        key = hashlib.sha256(f"{self.salt}\0{inputs}".encode()).hexdigest()
        old = self.old.get(name)
        if (
            old
            and old[0] == key
            and all(
                output_unchanged(self.output, rel, self.manifest, digest)
                for rel, digest in old[1].items()
            )
        ):
            for rel, digest in old[1].items():
                files[rel] = OutFile(digest, source=self.output / rel)
            self.new[name] = old
            return
        made = {rel: from_bytes(data) for rel, data in make().items()}
        files.update(made)
        self.new[name] = (key, {rel: f.digest for rel, f in made.items()})


def _finish(
    config: Config,
    tree,
    content_name: str,
    theme: Theme,
    site,
    base: dict,
    menus,
    renders: dict,
    files: dict[str, OutFile],
    diags: Diagnostics,
    reuse: SiteWide,
    scratch: Path,
) -> None:
    """The site-wide files: special pages, theme assets, search index, sitemap, copied assets."""
    reuse.add(
        files,
        "pages",
        repr((base, full_tree(site))),
        lambda: special_pages(theme, site, base, menus),
    )
    reuse.add(files, "assets", "", theme.assets)
    index = scratch / "assets" / "search-index.js"
    index.parent.mkdir(parents=True, exist_ok=True)
    digest = write_search_script(index, _search_pages(site, renders))
    files["assets/search-index.js"] = OutFile(digest, source=index, move=True)
    files[".nojekyll"] = from_bytes(b"")
    if config.base_url:
        files["sitemap.xml"] = from_bytes(sitemap_xml(site, config.base_url))
    for asset in tree.assets:
        rel = str(asset.rel)
        if rel in files:
            diags.error(f"{content_name}/{rel}", None, "", f"clashes with a generated file '{rel}'")
            continue
        files[rel] = OutFile(asset.digest, source=asset.path)


def _template_cache(theme: Theme, cache_dir: Path) -> None:
    """Compiled templates kept in the cache (keyed by their source), not compiled every build."""
    import jinja2

    folder = cache_dir / "templates"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return  # an unwritable cache only costs time
    theme.env.bytecode_cache = jinja2.FileSystemBytecodeCache(str(folder))


def _render_markdown(site, frag: Fragments, store: FragmentStore, report: BuildReport):
    """Markdown -> fragments, reusing the cache for every source whose hash is unchanged; the
    misses are converted in worker processes when there are many (a cold build), each going
    to the fragment store as soon as it is made.

    Returns (url -> Rendered as a lazy mapping, url -> source key, url -> (ids, toc))."""
    from sitegen.markdown_render import RENDER_VERSION, Rendered, plain_text

    held: dict[str, Rendered] = {}
    sources: dict[str, str] = {}
    from_store: dict[str, str] = {}
    summaries: dict[str, tuple] = {}
    misses: dict[str, tuple[str, str, bool]] = {}  # key -> (key, text, strip first heading)
    stored = store.keys() if frag.markdown else set()
    for node in site.order:
        src = node.source
        if src is None:  # a folder without index.md: the template lists its children
            held[node.url] = Rendered("", [], [], "")
            summaries[node.url] = ([], [])
            continue
        if src.body_html is not None:
            rendered = Rendered(
                src.body_html, src.toc or [], _ids(src.body_html), plain_text(src.body_html)
            )
            held[node.url] = rendered
            summaries[node.url] = (rendered.ids, rendered.toc)
            sources[node.url] = hashlib.sha256(src.body_html.encode()).hexdigest()
            continue
        key = hashlib.sha256(
            f"{RENDER_VERSION}\0{node.strip_first_heading}\0{src.text}".encode()
        ).hexdigest()
        sources[node.url] = from_store[node.url] = key
        if key not in frag.markdown or key not in stored:
            misses.setdefault(key, (key, src.text, node.strip_first_heading))

    def convert(tasks) -> list:
        made = _convert([(text, strip) for _key, text, strip in tasks])
        store.put_many((key, r) for (key, _t, _s), r in zip(tasks, made, strict=True))
        return [(r.ids, r.toc, r.directives) for r in made]

    tasks = list(misses.values())
    if tasks:
        _convert([])  # the renderer is made once, here, and inherited by the workers
    done = run_chunks(tasks, convert, recycle=None)
    for (key, _t, _s), summary in zip(tasks, done, strict=True):
        frag.markdown[key] = summary
    report.markdown_rendered += len(tasks)
    used = {key: frag.markdown[key] for key in from_store.values()}
    for url, key in from_store.items():
        summaries[url] = used[key][:2]
    frag.markdown = used
    return Renders(store, from_store, held), sources, summaries


def _search_pages(site, renders) -> Iterator[dict]:
    """Search entries one page at a time (each page's text read from the store on demand)."""
    for n in site.order:
        rendered = renders[n.url]
        yield {
            "title": n.title,
            "url": n.url,
            "path": [a.title for a in n.ancestors()],
            "text": rendered.text,
            "toc": rendered.toc,
        }


def _convert(tasks) -> list:
    """Convert (Markdown, strip first heading) pairs; one renderer per process, reset per page."""
    global _RENDERER
    from sitegen.markdown_render import MarkdownRenderer

    if _RENDERER is None:
        _RENDERER = MarkdownRenderer()
    return [_RENDERER.render(text, strip) for text, strip in tasks]


_RENDERER = None


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


@functools.cache
def _code_digest() -> str:
    """Our own code and the Markdown stack are inputs too: an upgrade must rebuild."""
    import markdown
    import pygments

    h = hashlib.sha256(f"{markdown.__version__}\0{pygments.__version__}".encode())
    for f in sorted(Path(__file__).parent.glob("*.py")):
        h.update(f.read_bytes())
    return h.hexdigest()
