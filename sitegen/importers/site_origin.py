"""Where an imported site was published: ``base_url`` for its ``sitegen.yml``.

A cmsimde site lives in a GitHub repository and is published by GitHub Pages at
``https://OWNER.github.io/REPO/``. sitegen needs that address (``base_url``) for its 404 page,
which GitHub serves at any depth under ``/REPO/`` and which finds its CSS through the
address's path; without it a deep 404 is unstyled. The import takes it from ``--base-url``,
else from the site folder's own git remote (``origin`` in ``.git/config``, read as a text
file: no git command, no network), else leaves it out and says how to set it.
"""

from __future__ import annotations

import re
from pathlib import Path
from urllib.parse import urlsplit

_GITHUB = re.compile(
    r"^(?:https?://(?:[^@/]+@)?github\.com/|git@github\.com:|ssh://git@github\.com/)"
    r"([A-Za-z0-9][A-Za-z0-9-]{0,38})/([A-Za-z0-9._-]{1,100}?)(?:\.git)?/?$"
)
_REMOTE = re.compile(r'^\s*\[remote\s+"([^"]+)"\]\s*$')
_URL = re.compile(r"^\s*url\s*=\s*(\S+)\s*$")


def pages_url(owner: str, repo: str) -> str:
    """GitHub Pages' address of a repository (a `OWNER.github.io` repository is the root)."""
    host = f"{owner.lower()}.github.io"
    return f"https://{host}/" if repo.lower() == host else f"https://{host}/{repo}/"


def remote_url(root: Path) -> str | None:
    """The ``origin`` remote (else the first remote) of the git repository at ``root``."""
    try:
        text = (root / ".git" / "config").read_text(encoding="utf-8", errors="replace")
    except OSError:
        return None
    remotes: dict[str, str] = {}
    current = None
    for line in text.splitlines():
        m = _REMOTE.match(line)
        if m:
            current = m.group(1)
            continue
        if line.lstrip().startswith("["):
            current = None
            continue
        m = _URL.match(line)
        if m and current is not None:
            remotes.setdefault(current, m.group(1))
    return remotes.get("origin") or next(iter(remotes.values()), None)


def published_url(root: Path, given: str | None) -> tuple[str | None, str]:
    """(base_url or None, a sentence for the report). A ``given`` address that is not an
    http(s) URL with a host gives (None, why): the caller stops with that message."""
    if given is not None:
        try:
            parts = urlsplit(given.strip())
        except ValueError:
            parts = None
        if parts is None or parts.scheme not in ("http", "https") or not parts.hostname:
            return None, f"base URL {given!r} is not an http(s) address with a host"
        url = given.strip() if given.strip().endswith("/") else given.strip() + "/"
        return url, f"base_url {url} (from --base-url)"
    remote = remote_url(root)
    m = _GITHUB.match(remote or "")
    if m:
        url = pages_url(m.group(1), m.group(2))
        return url, f"base_url {url} from the site's GitHub remote ({remote})"
    return None, ""


def missing_note() -> str:
    return (
        "no base_url: the site's repository is not known; give --base-url "
        "https://USER.github.io/REPO/ (a 404 page deep under /REPO/ needs it for its styles)"
    )
