"""``sitegen.yml``: the project's settings, validated with line numbers.

A typo in a key must not be silently ignored (the teacher would wonder why the setting does
nothing), so unknown keys and wrong types are errors that name the key and its line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from sitegen.errors import BuildError, Diagnostic

CONFIG_NAME = "sitegen.yml"
LANGUAGES = ("zh-TW", "en")
_SIZE = re.compile(r"^(\d{2,4})x(\d{2,4})$")


@dataclass(frozen=True)
class RosterConfig:
    """One roster published as a page."""

    name: str
    file: Path
    corrections: Path | None
    section: str
    title: str
    weight: int = 0


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


@dataclass(frozen=True)
class SimsConfig:
    section: str = "gallery"
    title: str = "Simulation gallery"
    width: int = 480
    height: int = 360
    fps: int = 20
    jobs: int | None = None
    timeout: float = 600.0
    clips: tuple[ClipConfig, ...] = ()


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
    source_file: Path | None = None
    raw: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)


# ---------------------------------------------------------------- schema checking


class _Checker:
    """Walks a YAML node tree, checking keys and types, remembering line numbers."""

    def __init__(self, file: str):
        self.file = file
        self.problems: list[Diagnostic] = []

    def fail(self, node: yaml.Node | None, key: str, message: str) -> None:
        line = node.start_mark.line + 1 if node is not None else None
        self.problems.append(Diagnostic(self.file, line, key, message))

    def mapping(self, node: yaml.Node, path: str, allowed: dict[str, str]) -> dict[str, yaml.Node]:
        if not isinstance(node, yaml.MappingNode):
            self.fail(node, path or "(top level)", "expected a mapping of keys to values")
            return {}
        out: dict[str, yaml.Node] = {}
        for knode, vnode in node.value:
            key = str(knode.value)
            full = f"{path}.{key}" if path else key
            if key not in allowed:
                self.fail(knode, full, f"unknown key (allowed: {', '.join(sorted(allowed))})")
            elif key in out:
                self.fail(knode, full, "key given twice")
            else:
                out[key] = vnode
        return out

    def scalar(self, node: yaml.Node, key: str, kind: str) -> Any:
        value = yaml.safe_load(yaml.serialize(node)) if node is not None else None
        ok = {
            "str": isinstance(value, str),
            "int": isinstance(value, int) and not isinstance(value, bool),
            "num": isinstance(value, (int, float)) and not isinstance(value, bool),
            "bool": isinstance(value, bool),
        }[kind]
        if not ok:
            names = {
                "str": "a string",
                "int": "a whole number",
                "num": "a number",
                "bool": "true or false",
            }
            self.fail(node, key, f"must be {names[kind]}, got {value!r}")
            return None
        return value


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
}
_ROSTER = {
    "name": "str",
    "file": "str",
    "corrections": "str",
    "section": "str",
    "title": "str",
    "weight": "int",
}
_SIMS = {
    "section": "str",
    "title": "str",
    "size": "str",
    "fps": "int",
    "jobs": "int",
    "timeout": "num",
    "clips": "list",
}
_CLIP = {
    "name": "str",
    "scenario": "str",
    "script": "str",
    "scene": "str",
    "seed": "int",
    "seconds": "num",
    "after": "num",
}


def _values(ck: _Checker, nodes: dict[str, yaml.Node], schema: dict[str, str], prefix: str) -> dict:
    out = {}
    for key, node in nodes.items():
        kind = schema[key]
        if kind in ("list", "map"):
            continue
        value = ck.scalar(node, f"{prefix}{key}", kind)
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
    ck = _Checker(file)
    try:
        node = yaml.compose(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark else None
        raise BuildError(
            "invalid sitegen.yml",
            [Diagnostic(file, line, "", f"not valid YAML: {getattr(exc, 'problem', exc)}")],
        ) from None
    if node is None:
        return Config(root=root, source_file=root / file)
    top = ck.mapping(node, "", _TOP)
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
    for key in ("content_dir", "output_dir"):
        if key in values:
            kwargs[key] = Path(values[key])
    if "templates_dir" in values:
        kwargs["templates_dir"] = Path(values["templates_dir"])
    if "rosters" in top:
        kwargs["rosters"] = tuple(_rosters(ck, top["rosters"], root))
    if "sims" in top:
        kwargs["sims"] = _sims(ck, top["sims"], root)
    if ck.problems:
        raise BuildError("invalid sitegen.yml", ck.problems)
    raw = yaml.safe_load(text) or {}
    return Config(root=root, source_file=root / file, raw=raw, **kwargs)


def _rosters(ck: _Checker, node: yaml.Node, root: Path) -> list[RosterConfig]:
    if not isinstance(node, yaml.SequenceNode):
        ck.fail(node, "rosters", "must be a list")
        return []
    out = []
    for i, item in enumerate(node.value):
        where = f"rosters[{i}]"
        nodes = ck.mapping(item, where, _ROSTER)
        v = _values(ck, nodes, _ROSTER, where + ".")
        if not (_require(ck, item, v, "name", where) and _require(ck, item, v, "file", where)):
            continue
        out.append(
            RosterConfig(
                name=v["name"],
                file=root / v["file"],
                corrections=root / v["corrections"] if "corrections" in v else None,
                section=v.get("section", ""),
                title=v.get("title", v["name"]),
                weight=v.get("weight", 0),
            )
        )
    return out


def _sims(ck: _Checker, node: yaml.Node, root: Path) -> SimsConfig | None:
    nodes = ck.mapping(node, "sims", _SIMS)
    v = _values(ck, nodes, _SIMS, "sims.")
    kwargs: dict[str, Any] = {
        k: v[k] for k in ("section", "title", "fps", "jobs", "timeout") if k in v
    }
    if "size" in v:
        m = _SIZE.match(v["size"])
        if not m:
            ck.fail(nodes["size"], "sims.size", "must look like 480x360")
        else:
            kwargs["width"], kwargs["height"] = int(m.group(1)), int(m.group(2))
    clips = []
    if "clips" in nodes:
        if not isinstance(nodes["clips"], yaml.SequenceNode):
            ck.fail(nodes["clips"], "sims.clips", "must be a list")
        else:
            for i, item in enumerate(nodes["clips"].value):
                where = f"sims.clips[{i}]"
                cv = _values(ck, ck.mapping(item, where, _CLIP), _CLIP, where + ".")
                if not _require(ck, item, cv, "name", where):
                    continue
                if ("scenario" in cv) == ("script" in cv):
                    ck.fail(item, where, "give exactly one of 'scenario' or 'script'")
                    continue
                if "script" in cv and "scene" not in cv:
                    ck.fail(item, f"{where}.scene", "is required with 'script'")
                    continue
                if "script" in cv:
                    cv["script"] = root / cv["script"]
                clips.append(ClipConfig(**cv))
    kwargs["clips"] = tuple(clips)
    return SimsConfig(**kwargs)


def load_config(root: Path) -> Config:
    """Load ``root/sitegen.yml`` if present; a folder without one gets the defaults."""
    path = root / CONFIG_NAME
    if not path.is_file():
        return Config(root=root, title=root.resolve().name or "Site")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise BuildError(
            "cannot read config", [Diagnostic(str(path), None, "", str(exc))]
        ) from None
    return parse_config(text, root, file=str(path))
