"""The Jinja2 theme: templates and static assets, project files overriding the defaults.

The default theme is the repo's ``templates/`` folder, installed as the package data
``sitegen.theme``; a project may put its own ``templates/`` beside ``sitegen.yml`` and any
file there replaces the default of the same name.
"""

from __future__ import annotations

import functools
import hashlib
import re
from pathlib import Path
from urllib.parse import quote


def default_theme_dir() -> Path:
    """The packaged theme, or the repo's ``templates/`` in a source checkout.

    An installed wheel holds the theme at ``sitegen/_theme/`` beside this module (package data
    of ``sitegen._theme``, mapped from ``templates/`` in pyproject.toml). That package has no
    ``__init__.py``, so ``importlib.resources.files`` would give a namespace ``MultiplexedPath``
    whose ``str()`` is not a path: the folder is found by its place instead."""
    installed = Path(__file__).resolve().parent / "_theme"
    if (installed / "base.html").is_file():
        return installed
    return Path(__file__).resolve().parents[1] / "templates"


def pygments_css() -> str:
    """Light and dark code colours, generated from Pygments so they match its markup."""
    from pygments.formatters import HtmlFormatter

    light = HtmlFormatter(style="default").get_style_defs(".highlight")
    # dark when the reader chose it, or the system is dark and the reader did not choose light
    dark = HtmlFormatter(style="monokai").get_style_defs("[data-theme=dark] .highlight")
    auto = HtmlFormatter(style="monokai").get_style_defs(":root:not([data-theme=light]) .highlight")
    css = f"{light}\n{dark}\n@media (prefers-color-scheme: dark) {{\n{auto}\n}}\n"
    css = re.sub(r"(\.highlight \{ )background: [^;]*; ", r"\1", css)  # the theme's panel shows
    return re.sub(r" */\*.*?\*/", "", css)  # Pygments' comments: a third of the bytes


def shrink(suffix: str, data: bytes) -> bytes:
    """Comments and indentation out of the theme's CSS and JS: every page loads them.

    Only what is safe without a parser: CSS block comments, whole-line ``//`` comments and
    leading spaces in JS (the theme's scripts hold no multi-line strings).
    """
    if suffix not in (".css", ".js"):
        return data
    text = data.decode("utf-8")
    if suffix == ".css":
        text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    lines = (line.strip() for line in text.split("\n"))
    kept = [x for x in lines if x and not (suffix == ".js" and x.startswith("//"))]
    return ("\n".join(kept) + "\n").encode("utf-8")


@functools.lru_cache(maxsize=4096)
def _quoted(path: str) -> str:
    """A path percent-encoded for an href (the ``u`` filter; a page's menu, breadcrumbs and
    pager quote the same few paths again and again)."""
    return quote(path, safe="/#-._~!$&'()*+,;=:@%")


class Theme:
    def __init__(self, project_dir: Path | None):
        self.dirs = [d for d in (project_dir, default_theme_dir()) if d is not None and d.is_dir()]

    @functools.cached_property
    def env(self):
        """Made on first use: a no-op build reads the theme's digest only, and importing
        Jinja2 would be a fifth of its time."""
        import jinja2

        from sitegen.theme_env import ThemeEnvironment  # dict attributes looked up directly

        env = ThemeEnvironment(
            loader=jinja2.FileSystemLoader([str(d) for d in self.dirs]),
            autoescape=True,
            undefined=jinja2.StrictUndefined,
            trim_blocks=False,
            keep_trailing_newline=True,
        )
        # tojson for scripts (assets/nav.js): UTF-8 text is smaller than \u escapes
        env.policies["json.dumps_kwargs"] = {"sort_keys": True, "ensure_ascii": False}
        env.filters["u"] = lambda path: _quoted(str(path))
        return env

    def assets(self) -> dict[str, bytes]:
        """Static files for ``assets/``: the project's override the defaults by name."""
        out: dict[str, bytes] = {}
        for d in reversed(self.dirs):
            folder = d / "assets"
            if folder.is_dir():
                for f in sorted(folder.rglob("*")):
                    if f.is_file() and not f.name.startswith("."):
                        data = f.read_bytes()
                        if not f.name.endswith(".min.js"):  # vendored, minified: as shipped
                            data = shrink(f.suffix, data)
                        out[f"assets/{f.relative_to(folder).as_posix()}"] = data
        out["assets/pygments.css"] = pygments_css().encode()
        return out

    def digest(self) -> str:
        """Hash of every template and asset, so a theme edit re-renders every page."""
        h = hashlib.sha256()
        for d in self.dirs:
            for f in sorted(d.rglob("*")):
                if f.is_file():
                    h.update(f.relative_to(d).as_posix().encode())
                    h.update(f.read_bytes())
        return h.hexdigest()

    def render(self, template: str, context: dict) -> str:
        return self.env.get_template(template).render(**context)
