"""``sitegen new DIR``: a working course site to start from, which builds at once.

The starter is a folder of real files (``sitegen/starter/``, installed with the package) so
what an author gets can be read and tested as it is. Two names are stored without their dot
(``gitignore``, ``github/``) because packaging tools skip dot-files; they get it back here.
A handful of ``@NAME@`` placeholders are filled in; YAML values are quoted as YAML.
"""

from __future__ import annotations

import json
import re
import sys
from importlib import resources
from pathlib import Path

from sitegen import DISTRIBUTION, RELEASE_TAG, REPOSITORY

RENAMES = {"gitignore": ".gitignore", "github": ".github"}
TEXT_SUFFIXES = {".md", ".yml", ".yaml", ".txt", ".svg", ""}


def starter_dir() -> Path:
    return Path(str(resources.files("sitegen") / "starter"))


PLACEHOLDER = "OWNER/REPO"
VERSIONED = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*\s*(\[[^\]]*\])?\s*(==|>=|<=|~=|!=|<|>)")


def requirement(spec: str | None = None) -> str:
    """The pip line a new site's CI installs sitegen with (its ``requirements.txt``).

    ``spec`` (``sitegen new --from``): a requirement as it is (``name @ url``, ``name==1.2``),
    a URL (``git+https://host/x/y@tag``, ``https://.../x.whl``, ``file://...``), or a path to
    a wheel or a source folder on this machine. Without it: the git URL and commit this sitegen
    was installed from (pip records them, PEP 610), else :data:`sitegen.REPOSITORY` at
    :data:`sitegen.RELEASE_TAG`."""
    if spec:
        spec = spec.strip()
        if " @ " in spec or VERSIONED.match(spec):
            return spec
        if "://" in spec:
            if "+" in spec.split("://")[0] and spec.split("://", 1)[1].startswith("/"):
                # git+file:///path: pip before 23.1 refuses it after "name @ "; bare it is valid
                return spec
            return f"{DISTRIBUTION} @ {spec}"
        path = Path(spec).expanduser()
        if not path.exists():
            raise ValueError(f"--from {spec}: no such file or folder, and not a URL")
        return f"{DISTRIBUTION} @ {path.resolve().as_uri()}"
    installed = _installed_from_git()
    if installed:
        return f"{DISTRIBUTION} @ {installed}"
    return f"{DISTRIBUTION} @ git+{REPOSITORY}@{RELEASE_TAG}"


def _installed_from_git() -> str | None:
    """``git+URL@COMMIT`` when this sitegen was pip-installed from a remote git repository."""
    from importlib import metadata

    try:
        raw = metadata.distribution(DISTRIBUTION).read_text("direct_url.json")
        info = json.loads(raw or "{}")
    except (metadata.PackageNotFoundError, ValueError):
        return None
    vcs, url = info.get("vcs_info") or {}, str(info.get("url") or "")
    if vcs.get("vcs") != "git" or not vcs.get("commit_id") or url.startswith("file:"):
        return None
    return f"git+{url}@{vcs['commit_id']}"


def _yaml_str(text: str) -> str:
    return json.dumps(text, ensure_ascii=False)  # a JSON string is a valid YAML scalar


def plan(target: Path, title: str, language: str, pip_line: str) -> dict[str, bytes]:
    """Every file to write, relative to ``target``, with the placeholders filled in."""
    values = {
        "@TITLE@": title,
        "@LANGUAGE@": language,
        "@REQUIREMENT@": pip_line,
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


def new_site(
    target: Path,
    title: str | None,
    language: str,
    verbosity: int = 0,
    source: str | None = None,
) -> int:
    """Create the site; refuse (exit 1, nothing written) when ``target`` has files in it."""
    if target.exists() and (not target.is_dir() or any(target.iterdir())):
        print(f"sitegen new: error: {target} exists and is not an empty folder", file=sys.stderr)
        return 1
    try:
        pip_line = requirement(source)
    except ValueError as exc:
        print(f"sitegen new: error: {exc}", file=sys.stderr)
        return 2
    title = title or target.resolve().name or "Course site"
    files = plan(target, title, language, pip_line)
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
    if PLACEHOLDER in pip_line:
        print(
            f"sitegen new: warning: {target / 'requirements.txt'}: CI would install sitegen from "
            f"the placeholder {REPOSITORY}: write where sitegen is there (or run sitegen new "
            "--from SPEC: a git URL with a tag or commit, or a wheel's URL)",
            file=sys.stderr,
        )
    return 0
