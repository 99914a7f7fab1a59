"""The site-wide files of a build: special pages, theme assets, search index, sitemap, and
the content folder's other files, copied as they are.

Each depends on the whole site, so each is made again only when the hash of its inputs
changed or its output file was touched (:class:`SiteWide`): a one-page edit does not
re-render a 1000-entry Site Map.
"""

from __future__ import annotations

import contextlib
import hashlib
import mmap
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from sitegen.markdown_stage import search_records
from sitegen.nav import Site, full_tree
from sitegen.output import OutFile, Survey, from_bytes
from sitegen.pages import Menus, sitemap_xml, special_pages
from sitegen.search import record_key, write_search_script

if TYPE_CHECKING:
    from sitegen.build_inputs import SiteStage


@dataclass
class SiteWide:
    """Generated files that depend on the whole site (Site Map, search page, theme assets):
    made again only when their inputs' hash changed or the output file was touched."""

    output: Path
    manifest: dict[str, list]
    found: Survey  # the output folder as the build found it
    old: dict[str, tuple[str, dict[str, str]]]
    salt: str  # theme digest and library versions
    old_search: tuple = ()  # the last build's search index rows (sitegen.search.IndexRows)
    new: dict[str, tuple[str, dict[str, str]]] = field(default_factory=dict)
    search: tuple = ()  # this build's

    def add(self, files: dict[str, OutFile], name: str, inputs: str, make) -> None:
        key = hashlib.sha256(f"{self.salt}\0{inputs}".encode()).hexdigest()
        old = self.old.get(name)
        if (
            old
            and old[0] == key
            and all(
                self.found.unchanged(self.manifest, rel, digest) for rel, digest in old[1].items()
            )
        ):
            for rel, digest in old[1].items():
                files[rel] = OutFile(digest, source=self.output / rel)
            self.new[name] = old
            return
        made = {rel: from_bytes(data) for rel, data in make().items()}
        files.update(made)
        self.new[name] = (key, {rel: f.digest for rel, f in made.items()})


def search_index(path: Path, site: Site, renders, reuse: SiteWide) -> str:
    """Write the search index to ``path``, copying from the last build's index every record
    whose inputs are unchanged (sitegen.search.write_search_script); returns its digest."""
    keys = []
    for n in site.order:
        source = "" if n.url in renders.held else renders.keys_by_url.get(n.url, "")
        path_titles = [a.title for a in n.ancestors()]
        keys.append(
            (n.url, record_key(reuse.salt, n.title, n.url, path_titles, source) if source else "")
        )
    order = site.order
    old = reuse.old_search
    rel = "assets/search-index.js"
    with contextlib.ExitStack() as stack:
        previous = None
        if old and reuse.found.unchanged(reuse.manifest, rel, old[0]):
            fh = stack.enter_context(open(reuse.output / rel, "rb"))
            mm = stack.enter_context(mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ))
            previous = (mm, old[1])
        reuse.search = write_search_script(
            path, keys, lambda at: search_records([order[i] for i in at], renders), previous
        )
    return reuse.search[0]


def site_files(stage: SiteStage, menus: Menus, files: dict[str, OutFile], reuse: SiteWide) -> None:
    """Add the site-wide files to ``files``; a content file clashing with one is an error."""
    inp, site, base, diags = stage.inp, stage.site, stage.base, stage.diags
    theme, tree, content_name = inp.theme, inp.tree, inp.content_root.name
    reuse.add(
        files,
        "pages",
        repr((base, full_tree(site))),
        lambda: special_pages(theme, site, base, menus),
    )
    reuse.add(files, "assets", "", theme.assets)
    index = stage.scratch / "assets" / "search-index.js"
    index.parent.mkdir(parents=True, exist_ok=True)
    digest = search_index(index, site, stage.md.renders, reuse)
    files["assets/search-index.js"] = OutFile(digest, source=index, move=True)
    files[".nojekyll"] = from_bytes(b"")
    if inp.config.base_url:
        files["sitemap.xml"] = from_bytes(sitemap_xml(site, inp.config.base_url))
    for asset in tree.assets:
        rel = str(asset.rel)
        if rel in files:
            diags.error(f"{content_name}/{rel}", None, "", f"clashes with a generated file '{rel}'")
            continue
        files[rel] = OutFile(asset.digest, source=asset.path)


def make_site_files(stage: SiteStage, menus: Menus, files: dict[str, OutFile]) -> SiteWide:
    """Stage 5: the integrations' files made from the rendered site (slide decks, blog index,
    tags, feed), then the site-wide files. Returns the site-wide files' cache entries."""
    from sitegen.build_inputs import code_digest
    from sitegen.integrations import Built

    inp, site, diags = stage.inp, stage.site, stage.diags
    name = inp.content_root.name
    built = Built(
        site, stage.md.renders, stage.targets, stage.handlers, inp.theme, stage.base, menus, name
    )
    for integ in inp.integrations:
        for rel, data in integ.site_files(built, diags).items():
            if rel in files:
                diags.error(rel, None, "", "a generated file has the same path as a page")
            files[rel] = from_bytes(data)
    salt = f"{inp.theme_digest}\0{code_digest()}"
    frag = stage.frag
    reuse = SiteWide(inp.output, inp.state.manifest, inp.found, frag.site_wide, salt, frag.search)
    site_files(stage, menus, files, reuse)
    return reuse
