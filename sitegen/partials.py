"""Theme partials for the HTML integrations put into pages: the clip gallery, a clip's figure,
a roster.

That markup is made before any page is rendered (it becomes a page body or a directive's
output), so the integrations cannot use the build's page templates directly; they load the
same theme (a project's ``templates/`` first, then the default) and render a partial from
``templates/partials/``, so a project overrides the gallery or a roster like any page
template. Autoescape is on: every name, title and error reaches the HTML escaped.
"""

from __future__ import annotations

from markupsafe import Markup

from sitegen.config import Config
from sitegen.theme import Theme


class Partials:
    """Renders ``partials/NAME.html`` of the project's theme; the environment is made once."""

    def __init__(self, config: Config):
        self.theme = Theme(config.templates_path)

    def render(self, name: str, **context) -> str:
        return self.theme.render(f"partials/{name}.html", context)


def trusted(html: str) -> Markup:
    """HTML this program made and escaped already (a highlighted listing, a nested partial)."""
    return Markup(html)
