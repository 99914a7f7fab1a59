"""What rosters and simulation clips add to a build, behind one small interface.

Each integration may add generated pages (placed in the content tree like any other page),
extra output files, and ``::: NAME`` directive handlers; it contributes a fingerprint so the
no-op check notices when its inputs change.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

from sitegen.errors import Diagnostics
from sitegen.nav import PageInput
from sitegen.output import OutFile

if TYPE_CHECKING:
    from sitegen.cache import State


@dataclass
class Built:
    """The finished site, for integrations that make files from rendered pages (slide decks,
    blog lists): what :meth:`Integration.site_files` may read."""

    site: Any  # sitegen.nav.Site
    renders: dict  # url -> sitegen.markdown_render.Rendered
    targets: Any  # sitegen.links.LinkTargets
    handlers: dict  # directive name -> handler
    theme: Any  # sitegen.theme.Theme
    base: dict  # sitegen.pages.site_context
    menus: Any  # sitegen.pages.Menus
    content_name: str  # the content folder's name, for diagnostics


class RunOptions(Protocol):
    """What an integration may read of the build's options (``sitegen.build.BuildOptions``
    has these): where to log, whether a terminal shows live progress, whether to retry clips
    whose failure is remembered. Narrow on purpose: an integration needs no more of a build."""

    log: Callable[[str], None]
    is_tty: bool
    retry_failed: bool


class Integration:
    """Base class: does nothing. Subclasses override what they provide."""

    def adjust(self, inputs: list[PageInput], diags: Diagnostics) -> list[PageInput]:
        """Change content pages before the tree is built (a deck's separators, a post's
        order); called after :meth:`prepare`, before :meth:`pages`."""
        return inputs

    def site_files(self, built: Built, diags: Diagnostics) -> dict[str, bytes]:
        """Files made from the rendered site, published with the pages."""
        return {}

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
