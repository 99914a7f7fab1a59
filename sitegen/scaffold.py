"""``sitegen new DIR``: a working course site to start from, which builds at once.

The starter is a folder of real files (``sitegen/starter/``, installed with the package) so
what an author gets can be read and tested as it is. Two names are stored without their dot
(``gitignore``, ``github/``) because packaging tools skip dot-files; they get it back here.
A handful of ``@NAME@`` placeholders are filled in; YAML values are quoted as YAML.
"""

from __future__ import annotations

import json
import sys
from importlib import resources
from pathlib import Path

from sitegen import __version__

RENAMES = {"gitignore": ".gitignore", "github": ".github"}
TEXT_SUFFIXES = {".md", ".yml", ".yaml", ".txt", ".svg", ""}


def starter_dir() -> Path:
    return Path(str(resources.files("sitegen") / "starter"))


def requirement() -> str:
    """The pip line CI uses: this sitegen's version (edit it to a git URL if unreleased)."""
    return f"sitegen=={__version__}"


def _yaml_str(text: str) -> str:
    return json.dumps(text, ensure_ascii=False)  # a JSON string is a valid YAML scalar


def plan(target: Path, title: str, language: str) -> dict[str, bytes]:
    """Every file to write, relative to ``target``, with the placeholders filled in."""
    values = {
        "@TITLE@": title,
        "@LANGUAGE@": language,
        "@REQUIREMENT@": requirement(),
    }
    out: dict[str, bytes] = {}
    root = starter_dir()
    for path in sorted(root.rglob("*")):
        if not path.is_file() or "__pycache__" in path.parts:
            continue
        rel = path.relative_to(root)
        parts = [RENAMES.get(p, p) for p in rel.parts]
        data = path.read_bytes()
        if path.suffix in TEXT_SUFFIXES:
            text = data.decode("utf-8")
            for key, value in values.items():
                shown = _yaml_str(value) if path.suffix == ".yml" and key == "@TITLE@" else value
                text = text.replace(key, shown)
            data = text.encode("utf-8")
        out["/".join(parts)] = data
    return out


def new_site(target: Path, title: str | None, language: str, verbosity: int = 0) -> int:
    """Create the site; refuse (exit 1, nothing written) when ``target`` has files in it."""
    if target.exists() and (not target.is_dir() or any(target.iterdir())):
        print(f"sitegen new: error: {target} exists and is not an empty folder", file=sys.stderr)
        return 1
    title = title or target.resolve().name or "Course site"
    files = plan(target, title, language)
    for rel, data in files.items():
        path = target / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
        if verbosity > 0:
            print(f"  wrote {path}", file=sys.stderr)
    if verbosity >= 0:
        print(
            f"sitegen: created {target} ({len(files)} files). Next:\n"
            f"  cd {target} && sitegen serve     # preview at http://127.0.0.1:8000/\n"
            f"  sitegen build --strict           # the site in {target}/site/",
            file=sys.stderr,
        )
    return 0
