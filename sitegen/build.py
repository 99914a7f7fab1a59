"""``sitegen build``: the pipeline, with I/O at the edges.

config -> scan files -> integrations (rosters, clips) -> navigation -> Markdown (cached by
source hash) -> links and directives -> page contexts (rendered only when their hash
changes) -> site-wide files -> check -> publish atomically -> save the cache.
"""

from __future__ import annotations

import gc
import hashlib
import os
import shutil
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sitegen import __version__
from sitegen.build_inputs import Inputs, SiteStage, code_digest
from sitegen.cache import Cache, Fragments, State
from sitegen.config import Config, load_config
from sitegen.content import SourcePage, SourceTree, scan
from sitegen.errors import BuildError, Diagnostic, Diagnostics
from sitegen.integrations import Integration
from sitegen.output import intact as output_intact
from sitegen.output import output_lock, publish, survey
from sitegen.plugins import make_integrations
from sitegen.source_stats import stat_walk
from sitegen.theme import Theme

# Only what a no-op build needs is imported above; the Markdown, template and worker
# machinery is imported by the stages that use it (a no-op build is mostly start-up time).


@dataclass
class BuildOptions:
    """What ``sitegen build`` (or ``serve``) asks of one build."""

    source: Path = Path(".")
    output: Path | None = None
    strict: bool = False
    clean: bool = False  # every page rendered again, the output written afresh (clips: cache)
    cache_dir: Path | None = None
    log: Callable[[str], None] = lambda line: print(line, file=sys.stderr)
    is_tty: bool = False
    retry_failed: bool = False  # render clips whose failure the cache remembers (sims_pages)
    render_clips: bool = True  # False: cached clips only, placeholders for the rest (serve)


@dataclass
class BuildReport:
    """What a build did: counts, changed files, diagnostics, notes and time."""

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
    content = config.content_path
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


def to_input(page: SourcePage):
    """The navigation record of a content page; a text the page has not read yet is not read
    now either (sitegen.source_records)."""
    from sitegen.nav import PageInput
    from sitegen.page_text import deferred

    fields = {
        "rel": page.rel,
        "meta": page.meta,
        "is_index": page.is_index,
        "prefix": page.prefix,
        "stem": page.stem,
        "body_line": page.body_line,
        "digest": page.digest,
    }
    held = page.__dict__.get("_text_from")
    made = (
        deferred(PageInput, held, **fields)
        if held is not None
        else PageInput(text=page.text, **fields)
    )
    made.text_key, made.heading = page.text_key, page.heading
    return made


def build(opts: BuildOptions) -> BuildReport:
    """Build the site; raise :class:`BuildError` (previous site untouched) on errors.

    One build per output at a time: the output lock is held for the whole build (cache
    included); a second build raises BuildError at once (sitegen.output.output_lock)."""
    paths = resolve_paths(opts)
    with output_lock(paths[2]), collector_paused():
        return _build(opts, paths)


@contextmanager
def collector_paused() -> Iterator[None]:
    """Python's cyclic garbage collector off for the build (workers turn it back on: see
    sitegen.workers). A build holds tens of thousands of long-lived objects (the source
    records and caches it loaded, the site tree) and makes little cyclic garbage, so each
    full collection only walks the same live objects again: 60-80 ms of a 0.5 s one-page
    edit. Memory is freed by reference counting as before; what cycles a build leaves are
    collected after it."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def _build(opts: BuildOptions, paths: tuple[Config, Path, Path, Path]) -> BuildReport:
    """The stages, each a function over plain data: scan -> (up to date? stop) -> site tree
    (integrations' inputs included) -> Markdown -> pages -> site-wide files -> check ->
    publish -> save the cache."""
    started = time.perf_counter()
    diags = Diagnostics()
    inp = read_inputs(opts, paths, diags)
    report = BuildReport(output=paths[2])
    if inp is not None and up_to_date(opts, inp, diags):
        if inp.tree.stats_trusted and inp.tree.stats != inp.state.sources:
            # read in full because a file was new the last time: remember its stat key now,
            # so the next no-op needs no reading
            inp.state.sources, inp.state.rest = inp.tree.stats, inp.rest
            Cache(inp.cache_dir).save_state(inp.state)
        inp = None
    if inp is None:
        report.up_to_date = True
        report.seconds = time.perf_counter() - started
        return report

    from sitegen.fragment_store import FragmentStore
    from sitegen.i18n import strings
    from sitegen.links import LinkTargets
    from sitegen.markdown_stage import render_markdown, used_blocks
    from sitegen.page_jobs import links_digest, render_pages
    from sitegen.pages import site_context
    from sitegen.site_files import make_site_files

    t = strings(inp.config.language)
    inp.found = survey(inp.output, inp.state.manifest)
    _template_cache(inp.theme, inp.cache_dir)
    site, handlers = site_tree(inp, t, diags)
    cache = Cache(inp.cache_dir)
    frag = Fragments() if opts.clean else cache.load_fragments()
    store = FragmentStore(inp.cache_dir / "fragments.sqlite")
    if opts.clean:
        store.clear()
    md = render_markdown(site, frag, store, raw_html=inp.config.markdown.raw_html)
    report.markdown_rendered = md.converted
    assets = {a.rel for a in inp.tree.assets}
    targets = LinkTargets.build(site, assets, {url: set(s[0]) for url, s in md.summaries.items()})
    base = site_context(inp.config, t)
    salt = links_digest(targets) + "".join(integ.fingerprint() for integ in inp.integrations)
    scratch = inp.output.parent / f".{inp.output.name}.sitegen-building-{os.getpid()}-pages"
    shutil.rmtree(scratch, ignore_errors=True)
    scratch.mkdir(parents=True)
    stage = SiteStage(inp, site, md, targets, handlers, base, frag, salt, scratch, diags)
    try:
        phase, files, new_pages = render_pages(stage, report)
        reuse = make_site_files(stage, phase.menus, files)
        report.diagnostics = check(opts, diags)
        for integ in inp.integrations:
            files.update(integ.files())
            report.notes.extend(integ.notes(inp.state))
        manifest, report.changed = publish(
            inp.output, files, inp.state.manifest, inp.found, afresh=opts.clean
        )
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    clean = not diags.warnings
    new_state = State(
        inp.fingerprint if clean else "",
        str(inp.output),
        manifest,
        sources=inp.tree.stats if clean and inp.tree.stats_trusted else {},
        rest=inp.rest,
    )
    for integ in inp.integrations:
        integ.save(new_state)
    cache.save_state(new_state)
    cache.save_sources(inp.content_root.resolve(), inp.tree.records)
    frag.pages = new_pages
    frag.site_wide = reuse.new
    frag.search = reuse.search
    cache.save_fragments(frag)
    store.keep_only(set(frag.markdown), used_blocks(frag))
    store.close()
    report.seconds = time.perf_counter() - started
    return report


def read_inputs(opts: BuildOptions, paths: tuple, diags: Diagnostics) -> Inputs | None:
    """Stage 1: the config, the theme, the integrations and every source file (hashed);
    None when the build is a no-op known without reading the sources (their stat keys are
    those of the last build, whose output is intact)."""
    config, content_root, output, cache_dir = paths
    state = State() if opts.clean else Cache(cache_dir).load_state()
    theme = Theme(config.templates_path)
    theme_digest = theme.digest()
    integrations = make_integrations(config, cache_dir, opts)
    rest = _rest_digest(config, theme_digest, integrations)
    # every file's stat key, for the no-op check and then the scan; none before a first build
    walked = stat_walk(content_root, {output, cache_dir}) if state.output else None
    if (
        not opts.clean
        and _sources_unchanged(state, rest, output, walked)
        and output_intact(output, state.manifest)
    ):
        return None
    known = {} if opts.clean else Cache(cache_dir).load_sources(content_root.resolve())
    tree = scan(content_root, diags, exclude={output, cache_dir}, known=known, walked=walked)
    if config.source_file and config.source_file.parent.resolve() == content_root.resolve():
        # content_dir: "." (docs/ is one): the project's settings are not a file of the site
        tree.assets = [a for a in tree.assets if str(a.rel) != config.source_file.name]
    return Inputs(
        config,
        content_root,
        output,
        cache_dir,
        state,
        tree,
        theme,
        theme_digest,
        integrations,
        rest,
        _fingerprint(rest, tree),
    )


def up_to_date(opts: BuildOptions, inp: Inputs, diags: Diagnostics) -> bool:
    """A no-op: same inputs as the last build, which reported nothing, and its output intact."""
    return (
        not opts.clean
        and inp.state.fingerprint == inp.fingerprint
        and inp.state.output == str(inp.output)
        and not diags.items
        and output_intact(inp.output, inp.state.manifest)
    )


def site_tree(inp: Inputs, t: dict, diags: Diagnostics) -> tuple[Any, dict]:
    """Stage 2: the page inputs (content pages plus the integrations' own) -> the site tree;
    returns (site, directive handlers)."""
    from sitegen.nav import build_site

    inputs = [to_input(p) for p in inp.tree.pages]
    handlers: dict = {}
    for integ in inp.integrations:
        integ.prepare(diags, inp.state)
        inputs = integ.adjust(inputs, diags)  # slide separators, blog posts' order
        inputs.extend(integ.pages(t))
        handlers.update(integ.directives())
    _check_collisions(inputs, diags)
    return build_site(inputs, home_title=t["home"]), handlers


def check(opts: BuildOptions, diags: Diagnostics) -> list[Diagnostic]:
    """Stage 6: the diagnostics, sorted; raise BuildError (nothing published) on errors, or
    on warnings with ``--strict``."""
    found = sorted(diags.items, key=lambda d: (d.file, d.line or 0, d.message))
    if diags.errors or (opts.strict and diags.warnings):
        why = "errors" if diags.errors else "warnings (--strict)"
        raise BuildError(f"build failed with {why}; the previous site was left as it was", found)
    return found


def _template_cache(theme: Theme, cache_dir: Path) -> None:
    """Compiled templates kept in the cache (keyed by their source), not compiled every build."""
    import jinja2

    folder = cache_dir / "templates"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return  # an unwritable cache only costs time
    theme.env.bytecode_cache = jinja2.FileSystemBytecodeCache(str(folder))


def _check_collisions(inputs: list, diags: Diagnostics) -> None:
    seen: set[str] = set()
    for p in inputs:
        rel = str(p.rel)
        if rel in seen:
            diags.error(rel, None, "", "a generated page has the same path as a content page")
        seen.add(rel)


def _rest_digest(config: Config, theme_digest: str, integrations: list[Integration]) -> str:
    """Every input of the build but the content files."""
    h = hashlib.sha256()
    h.update(f"{__version__}\0{config!r}\0{theme_digest}\0{code_digest()}\0".encode())
    for integ in integrations:
        h.update(integ.fingerprint().encode())
    h.update(os.environ.get("SOURCE_DATE_EPOCH", "").encode())
    return h.hexdigest()


def _fingerprint(rest: str, tree: SourceTree) -> str:
    h = hashlib.sha256(rest.encode())
    for p in tree.pages:
        h.update(f"p\0{p.rel}\0{p.digest}\0".encode())
    for a in tree.assets:
        h.update(f"a\0{a.rel}\0{a.digest}\0".encode())
    return h.hexdigest()


def _sources_unchanged(
    state: State, rest: str, output: Path, walked: dict[str, list[int]] | None
) -> bool:
    """The last build was clean and nothing but the content could have changed since; each
    content file still has the stat key it had when that build read it, and none came or
    went. Stat keys only: nothing is read (a no-op of 1000 pages in milliseconds)."""
    return (
        bool(state.fingerprint and state.sources)
        and state.rest == rest
        and state.output == str(output)
        and walked == state.sources
    )
