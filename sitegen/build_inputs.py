"""What a build reads before it decides anything (the scan stage's result, plain data), and
the digest of the code that makes the site: shared by the build's stages
(``sitegen.build``, ``sitegen.page_jobs``, ``sitegen.site_files``)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from sitegen.cache import State
from sitegen.config import Config
from sitegen.content import SourceTree
from sitegen.integrations import Integration
from sitegen.output import Survey
from sitegen.theme import Theme


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


def code_digest() -> str:
    """The code that makes the site, as :func:`located.code_keys.code_key` keys it: the build's
    import closure (integrations, clips and rosters included) and the libraries it imports."""
    from located.code_keys import code_key

    return code_key("sitegen.build")
