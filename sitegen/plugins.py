"""The one table of integrations a build runs: rosters, the clip gallery, slide decks, the blog
and the redirects for old URLs.

Declared here rather than registered by importing a module for its side effect, so that a
reader sees every integration, the order they run in and what switches each on in one place,
and so the interface (:mod:`sitegen.integrations`) imports none of them: the integrations
import the interface, this table imports the integrations, and the build imports this table.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from sitegen.blog import BlogIntegration
from sitegen.config import Config
from sitegen.integrations import Integration, RunOptions
from sitegen.redirects import RedirectIntegration
from sitegen.roster_pages import RosterIntegration
from sitegen.sims_pages import SimsIntegration
from sitegen.slides import SlidesIntegration


@dataclass(frozen=True)
class Plugin:
    """One integration: its name, whether a project's config asks for it, how to make it."""

    name: str
    wanted: Callable[[Config], bool]
    make: Callable[[Config, Path, RunOptions], Integration]


INTEGRATIONS: tuple[Plugin, ...] = (
    Plugin("rosters", lambda c: bool(c.rosters), lambda c, _cache, _opts: RosterIntegration(c)),
    Plugin("sims", lambda c: c.sims is not None, SimsIntegration),
    Plugin("slides", lambda c: True, lambda c, _cache, _opts: SlidesIntegration(c)),
    Plugin("blog", lambda c: True, lambda c, _cache, _opts: BlogIntegration(c)),
    # last: its redirects must not take a path another integration made
    Plugin("redirects", lambda c: True, lambda c, cache, _opts: RedirectIntegration(c, cache)),
)


def make_integrations(config: Config, cache_dir: Path, opts: RunOptions) -> list[Integration]:
    """The integrations this project's config asks for, in the table's order."""
    return [p.make(config, cache_dir, opts) for p in INTEGRATIONS if p.wanted(config)]
