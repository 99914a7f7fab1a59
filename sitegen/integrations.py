"""What rosters and simulation clips add to a build, behind one small interface.

Each integration may add generated pages (placed in the content tree like any other page),
extra output files, and ``::: NAME`` directive handlers; it contributes a fingerprint so the
no-op check notices when its inputs change.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from sitegen.errors import Diagnostics
from sitegen.nav import PageInput
from sitegen.output import OutFile

if TYPE_CHECKING:
    from sitegen.build import BuildOptions
    from sitegen.cache import State
    from sitegen.config import Config


class Integration:
    """Base class: does nothing. Subclasses override what they provide."""

    def fingerprint(self) -> str:
        return ""

    def prepare(self, diags: Diagnostics, state: State) -> None:
        """Read inputs and do the expensive work once, reporting problems to ``diags``."""

    def pages(self, strings: dict[str, str]) -> list[PageInput]:
        return []

    def files(self) -> dict[str, OutFile]:
        return {}

    def directives(self) -> dict:
        return {}

    def notes(self, state: State) -> list[str]:
        return []

    def save(self, state: State) -> None:
        """Remember what the next build compares against (e.g. the roster for diffs)."""


def make_integrations(config: Config, cache_dir: Path, opts: BuildOptions) -> list[Integration]:
    out: list[Integration] = []
    if config.rosters:
        from sitegen.roster_pages import RosterIntegration

        out.append(RosterIntegration(config))
    if config.sims is not None:
        from sitegen.sims_pages import SimsIntegration

        out.append(SimsIntegration(config, cache_dir, opts))
    return out
