"""The ``sitegen.yml`` an import writes, so the imported site keeps its name and language.

A cmsimde site keeps its title in ``config/config`` (``siteTitle:...``) and has no notion of
an interface language; sitegen shows both in every page (header, menu words, ``<html
lang>``). Without this file the imported site was called "Course site" with English menus
even when every page was Chinese.

The file goes beside DEST (the project folder: ``sitegen build`` there builds DEST), with
``content_dir`` when DEST is not the default ``content``. An existing ``sitegen.yml`` is never
replaced -- it may hold rosters and clips -- the report says what it would have held instead.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from sitegen.importers import mdtext

CONFIG_NAME = "sitegen.yml"
_CJK = re.compile(r"[\u3400-\u4dbf\u4e00-\u9fff\uf900-\ufaff]")
_LATIN = re.compile(r"[A-Za-z]")
_FENCE = re.compile(r"^(```|~~~).*?^\1", re.S | re.M)
#: Not prose: inline code, raw HTML tags, link destinations and bare URLs.
_NOT_PROSE = re.compile(r"`[^`\n]*`|<[^>\n]*>|\]\([^)\n]*\)|https?://\S+")


def detect_language(texts: list[str]) -> str:
    """``zh-TW`` when the prose (code, tags and URLs left out) is Chinese enough, else ``en``.

    Chinese carries a word in one or two characters where English needs five letters, so
    a page whose prose is one tenth CJK characters by count reads as Chinese. Twenty
    characters at least, so a stray name in an English site does not switch it.
    """
    cjk = latin = 0
    for text in texts:
        prose = _NOT_PROSE.sub(" ", _FENCE.sub("", text))
        cjk += len(_CJK.findall(prose))
        latin += len(_LATIN.findall(prose))
    return "zh-TW" if cjk >= 20 and cjk * 10 >= cjk + latin else "en"


@dataclass
class ProjectConfig:
    """What the import writes into ``sitegen.yml``."""

    title: str
    language: str
    content_dir: str = "content"
    base_url: str | None = None  # where the site was published, when known (site_origin)

    def text(self, source: str) -> str:
        lines = [
            f"# Written by `sitegen import cmsimde` from {source}",
            f"title: {mdtext.yaml_string(self.title)}",
            f"language: {self.language}",
        ]
        if self.base_url:
            lines.append(f"base_url: {mdtext.yaml_string(self.base_url)}")
        if self.content_dir != "content":
            lines.append(f"content_dir: {mdtext.yaml_string(self.content_dir)}")
        return "\n".join(lines) + "\n"


def write_project_config(dest: Path, config: ProjectConfig, source: str) -> tuple[Path, str, bool]:
    """Write ``sitegen.yml`` beside ``dest``; return (its path, a sentence for the report,
    whether that sentence is a warning).

    Raises OSError when it cannot be written (the caller reports it with the path).
    """
    config.content_dir = dest.name
    path = dest.absolute().parent / CONFIG_NAME
    text = config.text(source)
    wanted = f"title {config.title!r}, language {config.language}"
    if config.base_url:
        wanted += f", base_url {config.base_url}"
    if path.exists():
        try:
            current = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            current = ""
        if current == text:
            return path, f"{path} already holds the imported site's settings ({wanted})", False
        return (
            path,
            (
                f"{path} exists and was left unchanged; the cmsimde site had {wanted}: "
                "set title and language there to keep them"
            ),
            True,
        )
    path.write_text(text, encoding="utf-8")
    return path, f"wrote {path} ({wanted})", False
