"""What a build reads before it decides anything (the scan stage's result, plain data), and
the digest of the code that makes the site: shared by the build's stages
(``sitegen.build``, ``sitegen.page_jobs``, ``sitegen.site_files``)."""

from __future__ import annotations

import functools
import hashlib
import importlib.util
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


@functools.cache
def code_digest() -> str:
    """Our own code and the Markdown stack are inputs too: an upgrade must rebuild. The
    libraries' version files are read, not imported (a no-op build needs neither)."""
    h = hashlib.sha256()
    for name, version_file in (("markdown", "__meta__.py"), ("pygments", "__init__.py")):
        spec = importlib.util.find_spec(name)
        origin = spec.origin if spec else None
        if origin:
            h.update(Path(origin).with_name(version_file).read_bytes())
    for f in sorted(Path(__file__).parent.glob("*.py")):
        h.update(f.read_bytes())
    return h.hexdigest()
