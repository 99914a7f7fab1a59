"""``sitegen.yml``: the project's settings, validated with line numbers.

A typo in a key must not be silently ignored (the teacher would wonder why the setting does
nothing), so unknown keys and wrong types are errors that name the key and its line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sims.clip_spec import CAMERAS, DEFAULT_CAMERA
from sitegen.config_paths import inside_project
from sitegen.errors import BuildError, Diagnostic
from sitegen.sweep_config import EXECUTORS, SweepConfig, parse_sweeps

if TYPE_CHECKING:
    # YAML is imported by the functions that parse a sitegen.yml: a folder without one (and
    # so a build that needs no YAML at all) does not pay ~25 ms to import it
    import yaml

    from located.yamlwalk import Walker as _Checker

CONFIG_NAME = "sitegen.yml"
LANGUAGES = ("zh-TW", "en")
_SIZE = re.compile(r"^(\d{2,4})x(\d{2,4})$")
MAX_TIMEOUT = 7 * 86400.0  # a week: longer limits overflow the clocks that wait on them
TIMEOUT_RULE = f"must be a positive number of seconds, at most {MAX_TIMEOUT:g} (a week)"


@dataclass(frozen=True)
class RosterConfig:
    """One roster published as a page."""

    name: str
    file: Path
    corrections: Path | None
    section: str
    title: str
    weight: int = 0
    layout: str = "auto"  # text rosters: auto or one of roster.detect.TEXT_LAYOUTS
    aliases: Path | None = None  # an id -> account list (roster.aliases), issue 30


@dataclass(frozen=True)
class ClipConfig:
    """One simulation clip shown in the gallery and embeddable with ``::: clip NAME``."""

    name: str
    scenario: str | None = None
    script: Path | None = None
    scene: str | None = None
    seed: int | None = None
    seconds: float | None = None
    after: float | None = None
    speed: float = 1.0  # time-lapse: 4 plays 80 simulated seconds in 20 s (docs/clips.md)
    timeout: float | None = None  # wall-clock safety net for this clip (default sims.timeout)
    camera: str = DEFAULT_CAMERA  # follow (chase camera) or overview (fixed, whole path)
    trail: bool = False  # draw the path travelled so far on the floor
    title: str | None = None  # gallery heading and caption link text (default: the name)
    keys: Path | None = None  # script clips: key presses for `import keyboard` (--keys format)
    args: tuple[str, ...] = ()  # script clips: the script's arguments (sys.argv[1:])
    python: str | None = None  # script clips: run the script in this interpreter (--python)
    description: str | None = None  # the gallery's text (default: the source's own, English)
    formats: tuple[str, ...] | None = None  # replay and/or video (default: sims.formats)


@dataclass(frozen=True)
class SimsConfig:
    """The ``sims:`` section: the clip gallery and its clips."""

    section: str = "gallery"
    title: str = "Simulation gallery"
    width: int = 480
    height: int = 360
    fps: int = 20
    jobs: int | None = None
    timeout: float = 600.0
    clips: tuple[ClipConfig, ...] = ()
    formats: tuple[str, ...] = ("replay",)  # every clip's formats: replay and/or video
    executor: str = "local"  # sweeps' runs: local worker processes or ray (docs/sweeps.md)
    sweeps: tuple[SweepConfig, ...] = ()  # sitegen/sweep_config.py


@dataclass(frozen=True)
class BlogConfig:
    """The blog (sitegen/blog.py): dated posts in ``dir`` of the content folder."""

    dir: str = "blog"
    title: str = ""  # default: the interface's word for "Blog"
    page_size: int = 10  # posts per index page


@dataclass(frozen=True)
class SlidesConfig:
    """Slide decks (sitegen/slides.py): every page under ``dir`` is a deck, as is any page
    with ``slides: true``."""

    dir: str = "slides"


@dataclass(frozen=True)
class MarkdownConfig:
    """``markdown:``: ``raw_html: keep`` (default: HTML written in a page reaches the site as
    written) or ``strip`` (only what Markdown itself writes, docs/security.md;
    sitegen/html_clean.py)."""

    raw_html: str = "keep"


@dataclass(frozen=True)
class Config:
    """Everything a build needs to know that is not content."""

    root: Path
    title: str = "Course site"
    language: str = "en"
    base_url: str | None = None
    course_repo: str = "cd2021"
    description: str = ""
    author: str = ""
    content_dir: Path = Path("content")
    templates_dir: Path | None = None
    output_dir: Path = Path("site")
    rosters: tuple[RosterConfig, ...] = ()
    sims: SimsConfig | None = None
    blog: BlogConfig = BlogConfig()
    slides: SlidesConfig = SlidesConfig()
    markdown: MarkdownConfig = MarkdownConfig()
    source_file: Path | None = None
    raw: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)

    @property
    def content_path(self) -> Path:
        """Where the pages are: ``content_dir`` of a project, the folder itself for a bare
        folder of Markdown (no sitegen.yml)."""
        return self.root / self.content_dir if self.source_file else self.root

    @property
    def templates_path(self) -> Path | None:
        """The project's own template folder: ``templates_dir:``, else ``templates/`` beside
        sitegen.yml; none for a bare folder of Markdown (the default theme only)."""
        if self.templates_dir:
            return self.root / self.templates_dir
        return self.root / "templates" if self.source_file else None


# ---------------------------------------------------------------- schema checking


# The shared line-numbered walker (``located.yamlwalk``, also used for rosters) reports wrong
# shapes and types, duplicate and unknown keys at their line.


_TOP = {
    "title": "str",
    "language": "str",
    "base_url": "str",
    "course_repo": "str",
    "description": "str",
    "author": "str",
    "content_dir": "str",
    "templates_dir": "str",
    "output_dir": "str",
    "rosters": "list",
    "sims": "map",
    "blog": "map",
    "slides": "map",
    "markdown": "map",
}
_MARKDOWN = {"raw_html": "str"}
_BLOG = {"dir": "str", "title": "str", "page_size": "int"}
_SLIDES = {"dir": "str"}
_ROSTER = {
    "name": "str",
    "file": "str",
    "corrections": "str",
    "section": "str",
    "title": "str",
    "weight": "int",
    "layout": "str",
    "aliases": "str",
}
_SIMS = {
    "section": "str",
    "title": "str",
    "size": "str",
    "fps": "int",
    "jobs": "int",
    "timeout": "num",
    "clips": "list",
    "formats": "list",
    "executor": "str",
    "sweeps": "list",
}
_CLIP = {
    "name": "str",
    "scenario": "str",
    "script": "str",
    "scene": "str",
    "seed": "int",
    "seconds": "num",
    "after": "num",
    "speed": "num",
    "timeout": "num",
    "camera": "str",
    "trail": "bool",
    "title": "str",
    "keys": "str",
    "args": "list",
    "python": "str",
    "description": "str",
    "formats": "list",
}
_SCRIPT_ONLY = ("keys", "args", "python")
CLIP_FORMATS = ("replay", "video")


def _formats(ck: _Checker, node: yaml.Node, where: str) -> tuple[str, ...] | None:
    """A ``formats:`` list: some of replay and video, at least one, each once."""
    import yaml

    items = node.value if isinstance(node, yaml.SequenceNode) else None
    values = [i.value for i in items or () if isinstance(i, yaml.ScalarNode)]
    if not items or len(values) != len(items) or any(v not in CLIP_FORMATS for v in values):
        ck.fail(node, where, "must be a list of replay and/or video, e.g. [replay, video]")
        return None
    return tuple(dict.fromkeys(values))


def _values(ck: _Checker, nodes: dict[str, yaml.Node], schema: dict[str, str], prefix: str) -> dict:
    out = {}
    for key, node in nodes.items():
        kind = schema[key]
        if kind in ("list", "map"):
            continue
        value = ck.value(node, f"{prefix}{key}", kind)
        if value is not None:
            out[key] = value
    return out


def _require(ck: _Checker, node: yaml.Node, values: dict, key: str, where: str) -> bool:
    if key not in values:
        ck.fail(node, f"{where}.{key}", "is required")
        return False
    return True


def parse_config(text: str, root: Path, file: str = CONFIG_NAME) -> Config:
    """Parse and validate config text; raise :class:`BuildError` listing every problem."""
    from located.yaml import YamlError, compose, to_python
    from located.yamlwalk import ROOT, Walker

    ck = Walker(file)
    try:
        node = compose(text, file)
    except YamlError as exc:  # a LocatedError: its diagnostic names file, line and column
        raise BuildError("invalid sitegen.yml", [exc.diagnostic]) from None
    if node is None:
        return Config(root=root, source_file=root / file)
    top = ck.keys(node, ROOT, _TOP)
    values = _values(ck, top, _TOP, "")
    kwargs: dict[str, Any] = {}
    for key in ("title", "base_url", "course_repo", "description", "author"):
        if key in values:
            kwargs[key] = values[key]
    if "language" in values:
        if values["language"] not in LANGUAGES:
            ck.fail(top["language"], "language", f"must be one of {', '.join(LANGUAGES)}")
        else:
            kwargs["language"] = values["language"]
    if "base_url" in values:
        url = values["base_url"]
        if not re.match(r"^https?://[^\s/]+(/[^\s]*)?$", url):
            ck.fail(
                top["base_url"],
                "base_url",
                "must be an http(s) URL, e.g. https://user.github.io/repo/",
            )
        else:
            kwargs["base_url"] = url if url.endswith("/") else url + "/"
    if "course_repo" in values and not re.match(r"^[A-Za-z0-9._-]+$", values["course_repo"]):
        ck.fail(
            top["course_repo"], "course_repo", "must be a repository name (letters, digits, . _ -)"
        )
    inside_project(ck, top, values, ("content_dir", "templates_dir"), "", root)
    for key in ("content_dir", "output_dir", "templates_dir"):  # the site may go anywhere
        if key in values:
            kwargs[key] = Path(values[key])
    if "rosters" in top:
        kwargs["rosters"] = tuple(_rosters(ck, top["rosters"], root))
    if "sims" in top:
        kwargs["sims"] = _sims(ck, top["sims"], root)
    if "blog" in top:
        v = _values(ck, ck.keys(top["blog"], "blog", _BLOG), _BLOG, "blog.")
        if "page_size" in v and not 1 <= v["page_size"] <= 1000:
            ck.fail(top["blog"], "blog.page_size", "must be a whole number from 1 to 1000")
            del v["page_size"]
        kwargs["blog"] = BlogConfig(**_folder(ck, top["blog"], v, "blog"))
    if "slides" in top:
        v = _values(ck, ck.keys(top["slides"], "slides", _SLIDES), _SLIDES, "slides.")
        kwargs["slides"] = SlidesConfig(**_folder(ck, top["slides"], v, "slides"))
    if "markdown" in top:
        nodes = ck.keys(top["markdown"], "markdown", _MARKDOWN)
        v = _values(ck, nodes, _MARKDOWN, "markdown.")
        if "raw_html" in v and v["raw_html"] not in ("keep", "strip"):
            ck.fail(nodes["raw_html"], "markdown.raw_html", "must be keep or strip")
            del v["raw_html"]
        kwargs["markdown"] = MarkdownConfig(**v)
    if ck.problems:
        raise BuildError("invalid sitegen.yml", ck.problems)
    raw = to_python(node) or {}
    return Config(root=root, source_file=root / file, raw=raw, **kwargs)


def _folder(ck: _Checker, node: yaml.Node, values: dict, where: str) -> dict:
    """``dir`` must name a folder inside the content folder: no absolute path, no '..'."""
    d = values.get("dir")
    if d is not None:
        parts = d.strip("/").split("/")
        if d.startswith("/") or not d.strip("/") or any(x in ("", ".", "..") for x in parts):
            ck.fail(node, f"{where}.dir", "must be a folder inside the content folder, e.g. blog")
            del values["dir"]
        else:
            values["dir"] = "/".join(parts)
    return values


def _rosters(ck: _Checker, node: yaml.Node, root: Path) -> list[RosterConfig]:
    import yaml

    if not isinstance(node, yaml.SequenceNode):
        ck.fail(node, "rosters", "must be a list")
        return []
    out = []
    for i, item in enumerate(node.value):
        where = f"rosters[{i}]"
        nodes = ck.keys(item, where, _ROSTER)
        v = _values(ck, nodes, _ROSTER, where + ".")
        if not (_require(ck, item, v, "name", where) and _require(ck, item, v, "file", where)):
            continue
        if not inside_project(ck, nodes, v, ("file", "corrections", "aliases"), where + ".", root):
            continue
        out.append(
            RosterConfig(
                name=v["name"],
                file=root / v["file"],
                corrections=root / v["corrections"] if "corrections" in v else None,
                section=v.get("section", ""),
                title=v.get("title", v["name"]),
                weight=v.get("weight", 0),
                layout=v.get("layout", "auto"),
                aliases=root / v["aliases"] if "aliases" in v else None,
            )
        )
        from roster.detect import LAYOUTS

        if out[-1].layout not in LAYOUTS:
            ck.fail(nodes["layout"], f"{where}.layout", f"must be one of {', '.join(LAYOUTS)}")
    return out


def _sims(ck: _Checker, node: yaml.Node, root: Path) -> SimsConfig | None:
    import yaml

    nodes = ck.keys(node, "sims", _SIMS)
    v = _values(ck, nodes, _SIMS, "sims.")
    kwargs: dict[str, Any] = {
        k: v[k] for k in ("section", "title", "fps", "jobs", "timeout", "executor") if k in v
    }
    if v.get("executor", "local") not in EXECUTORS:
        ck.fail(nodes["executor"], "sims.executor", f"must be one of {', '.join(EXECUTORS)}")
        del kwargs["executor"]
    if "sweeps" in nodes:
        kwargs["sweeps"] = parse_sweeps(ck, nodes["sweeps"], root)
    if "timeout" in v and not 0 < v["timeout"] <= MAX_TIMEOUT:
        ck.fail(nodes["timeout"], "sims.timeout", TIMEOUT_RULE)
        del kwargs["timeout"]
    if "size" in v:
        m = _SIZE.match(v["size"])
        if not m:
            ck.fail(nodes["size"], "sims.size", "must look like 480x360")
        else:
            kwargs["width"], kwargs["height"] = int(m.group(1)), int(m.group(2))
    if "formats" in nodes:
        formats = _formats(ck, nodes["formats"], "sims.formats")
        if formats is not None:
            kwargs["formats"] = formats
    clips = []
    if "clips" in nodes:
        if not isinstance(nodes["clips"], yaml.SequenceNode):
            ck.fail(nodes["clips"], "sims.clips", "must be a list")
        else:
            for i, item in enumerate(nodes["clips"].value):
                where = f"sims.clips[{i}]"
                item_keys = ck.keys(item, where, _CLIP)
                cv = _values(ck, item_keys, _CLIP, where + ".")
                if not _require(ck, item, cv, "name", where):
                    continue
                if "formats" in item_keys:
                    cv["formats"] = _formats(ck, item_keys["formats"], f"{where}.formats")
                    if cv["formats"] is None:
                        continue
                if ("scenario" in cv) == ("script" in cv):
                    ck.fail(item, where, "give exactly one of 'scenario' or 'script'")
                    continue
                if "script" in cv and "scene" not in cv:
                    ck.fail(item, f"{where}.scene", "is required with 'script'")
                    continue
                paths = ("script", "scene", "keys", "python")
                if not inside_project(ck, item_keys, _paths(cv, paths), paths, where + ".", root):
                    continue
                if "script" in cv:
                    cv["script"] = root / cv["script"]
                extra = [k for k in _SCRIPT_ONLY if k in item_keys]
                if extra and "script" not in cv:
                    ck.fail(item, f"{where}.{extra[0]}", "applies to 'script' clips only")
                    continue
                if not _script_extras(ck, item_keys, cv, root, where):
                    continue
                if "speed" in cv and not 1 <= cv["speed"] <= 100:
                    ck.fail(item, f"{where}.speed", "must be a number from 1 to 100")
                    continue
                if "timeout" in cv and not 0 < cv["timeout"] <= MAX_TIMEOUT:
                    ck.fail(item, f"{where}.timeout", TIMEOUT_RULE)
                    continue
                if cv.get("camera", DEFAULT_CAMERA) not in CAMERAS:
                    ck.fail(item, f"{where}.camera", f"must be {' or '.join(CAMERAS)}")
                    continue
                clips.append(ClipConfig(**cv))
    kwargs["clips"] = tuple(clips)
    return SimsConfig(**kwargs)


def _paths(values: dict, keys: tuple[str, ...]) -> dict:
    """The values under ``keys`` that name files: ``python:`` may be a command name instead."""
    out = {k: values[k] for k in keys if k in values}
    if "python" in out and "/" not in out["python"] and "\\" not in out["python"]:
        del out["python"]
    return out


def _script_extras(ck: _Checker, nodes: dict, cv: dict, root: Path, where: str) -> bool:
    """A script clip's ``keys:`` (a key file inside the project), ``args:`` (a list of
    strings) and ``python:`` (an interpreter: a command name, or a path inside the project)."""
    import yaml

    if "args" in nodes:
        node = nodes["args"]
        items = node.value if isinstance(node, yaml.SequenceNode) else None
        if items is None or not all(isinstance(i, yaml.ScalarNode) for i in items):
            ck.fail(node, f"{where}.args", "must be a list of strings")
            return False
        cv["args"] = tuple(str(i.value) for i in items)
    if "keys" in cv:
        keys = root / cv["keys"]
        if not keys.is_file():
            ck.fail(nodes["keys"], f"{where}.keys", f"no such key file: {cv['keys']}")
            return False
        cv["keys"] = keys
    if "python" in cv and ("/" in cv["python"] or "\\" in cv["python"]):
        cv["python"] = str(root / cv["python"])
    return True


def load_config(root: Path) -> Config:
    """Load ``root/sitegen.yml`` if present; a folder without one gets the defaults."""
    path = root / CONFIG_NAME
    if not path.is_file():
        return Config(root=root, title=root.resolve().name or "Site")
    from located.yaml import MAX_BYTES

    try:
        if path.stat().st_size > MAX_BYTES:
            raise BuildError(
                "invalid sitegen.yml",
                [Diagnostic(str(path), None, "", f"larger than the limit of {MAX_BYTES} bytes")],
            )
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise BuildError(
            "cannot read config", [Diagnostic(str(path), None, "", str(exc))]
        ) from None
    return parse_config(text, root, file=str(path))
