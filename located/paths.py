"""Absolute paths in a message, made fit to publish: relative to the project, or a file name.

Why: an error text can travel from this machine into a published page (a clip that failed
shows its error in the gallery and in the search index). An absolute path there says how the
machine is laid out (``/home/alice/...``, ``/tmp/sitegen-lua-x1y2/...``) or what a script tried
to read (``/etc/shadow``). :func:`public_paths` rewrites every absolute POSIX path in a text: a
path inside ``root`` becomes relative to it (``scenes/a.ttt``), any other path ``…/NAME`` (its
last part only). Text that is not a path (URLs, ``a/b``, numbers) is left alone.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

# A path starts with "/" that does not follow a letter, digit, "." "/" ":" or "~" (so not the
# middle of "a/b", "./x" or a URL); it runs to white space, a quote or a bracket, or a ":"
# (``file.py:12``), "," or ";".
_PATH = re.compile(r"(?<![\w./:~])/[^\s'\"`<>()\[\]{},;:]*")


def public_paths(text: str, root: str | os.PathLike[str]) -> str:
    """``text`` with each absolute path relative to ``root`` when inside it, else ``…/NAME``."""
    base = os.path.realpath(root)
    bases = {os.path.normpath(str(root)), base}

    def rewrite(m: re.Match[str]) -> str:
        path = m.group(0)
        if path == "/":
            return path
        for b in bases:
            if path == b:
                return "."
            if path.startswith(b.rstrip("/") + "/"):
                return path[len(b.rstrip("/")) + 1 :]
        name = Path(path).name
        return f"…/{name}" if name else "…"

    return _PATH.sub(rewrite, text)
