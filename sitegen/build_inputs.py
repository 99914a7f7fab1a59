"""The records a build's stages hand each other: what a build reads before it decides anything
(:class:`Inputs`, the scan stage's result) and what pages and site-wide files are made from
(:class:`SiteStage`), and the digest of the code that makes the site; shared by the stages
(``sitegen.build``, ``sitegen.page_jobs``, ``sitegen.site_files``)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sitegen.cache import State
from sitegen.config import Config
from sitegen.content import SourceTree
from sitegen.integrations import Integration
from sitegen.output import Survey
from sitegen.theme import Theme

if TYPE_CHECKING:
    from sitegen.cache import Fragments
    from sitegen.errors import Diagnostics
    from sitegen.links import LinkTargets
    from sitegen.markdown_stage import MarkdownStage
    from sitegen.nav import Site


@dataclass
class Inputs:
    """Stage 1 (scan): everything the build reads before it decides anything."""

    config: Config
    content_root: Path
    output: Path
    cache_dir: Path
    state: State
    tree: SourceTree
    theme: Theme
    theme_digest: str
    integrations: list[Integration]
    rest: str  # the digest of every input but the content files
    fingerprint: str
    #: the output folder as the build found it (sitegen.output.survey), once it is known
    #: that the build is not a no-op
    found: Survey = field(default_factory=Survey)


@dataclass
class SiteStage:
    """Stages 2-3 (site tree, Markdown, link targets): what the page stage and the site-wide
    files are made from, and where they write (``scratch``) and report (``diags``)."""

    inp: Inputs
    site: Site
    md: MarkdownStage
    targets: LinkTargets
    handlers: dict[str, Any]  # directive name -> integration handler
    base: dict[str, Any]  # the site context every template gets (sitegen.pages.site_context)
    frag: Fragments  # the last build's cache entries; the new ones are written into it
    salt: str  # the links digest and the integrations' fingerprints
    scratch: Path
    diags: Diagnostics


def code_digest() -> str:
    """The code that makes the site, as :func:`located.code_keys.code_key` keys it: the build's
    import closure (integrations, clips and rosters included) and the libraries it imports."""
    from located.code_keys import code_key

    return code_key("sitegen.build")
