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

from sitegen.config import Config
from sitegen.integrations import Integration, RunOptions


@dataclass(frozen=True)
class Plugin:
    """One integration: its name, whether a project's config asks for it, how to make it."""

    name: str
    wanted: Callable[[Config], bool]
    make: Callable[[Config, Path, RunOptions], Integration]


# Each maker imports its integration: a project without rosters or clips does not pay for
# importing the roster reader or the simulator glue (~50 ms of every build's start).
def _rosters(config: Config, _cache: Path, _opts: RunOptions) -> Integration:
    from sitegen.roster_pages import RosterIntegration

    return RosterIntegration(config)


def _sims(config: Config, cache: Path, opts: RunOptions) -> Integration:
    from sitegen.sims_pages import SimsIntegration

    return SimsIntegration(config, cache, opts)


def _sweeps(config: Config, cache: Path, opts: RunOptions) -> Integration:
    from sitegen.sweeps_pages import SweepsIntegration

    return SweepsIntegration(config, cache, opts)


def _slides(config: Config, _cache: Path, _opts: RunOptions) -> Integration:
    from sitegen.slides import SlidesIntegration

    return SlidesIntegration(config)


def _blog(config: Config, _cache: Path, _opts: RunOptions) -> Integration:
    from sitegen.blog import BlogIntegration

    return BlogIntegration(config)


def _redirects(config: Config, cache: Path, _opts: RunOptions) -> Integration:
    from sitegen.redirects import RedirectIntegration

    return RedirectIntegration(config, cache)


INTEGRATIONS: tuple[Plugin, ...] = (
    Plugin("rosters", lambda c: bool(c.rosters), _rosters),
    Plugin("sims", lambda c: c.sims is not None, _sims),
    # also for sims.executor: ray alone: it sends the build's clips to Ray too
    Plugin(
        "sweeps",
        lambda c: c.sims is not None and (bool(c.sims.sweeps) or c.sims.executor != "local"),
        _sweeps,
    ),
    Plugin("slides", lambda c: True, _slides),
    Plugin("blog", lambda c: True, _blog),
    # last: its redirects must not take a path another integration made
    Plugin("redirects", lambda c: True, _redirects),
)


def make_integrations(config: Config, cache_dir: Path, opts: RunOptions) -> list[Integration]:
    """The integrations this project's config asks for, in the table's order."""
    return [p.make(config, cache_dir, opts) for p in INTEGRATIONS if p.wanted(config)]
