"""Paths that sitegen.yml names lie inside the project (docs/security.md)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from yaml import Node

    from located.yamlwalk import Walker


def inside_project(
    ck: Walker, nodes: dict[str, Node], values: dict, keys: tuple[str, ...], where: str,
    root: Path,
) -> bool:  # fmt: skip
    """Every path ``values`` gives under ``keys`` lies inside the project (the folder of
    ``sitegen.yml``), symlinks followed: a file sitegen.yml names is read and may be published,
    so one outside (``/tmp/roster.txt``, ``../x``) is an error at its line (docs/security.md).
    A bundled scene name is a name inside the project too. False after reporting one."""
    base = root.resolve()
    for key in keys:
        value = values.get(key)
        if value is None:
            continue
        path = Path(str(value)).expanduser()
        if path.is_absolute() or not (root / path).resolve().is_relative_to(base):
            ck.fail(
                nodes.get(key),
                f"{where}{key}",
                f"must be a path inside the project (the folder of sitegen.yml), not {value}",
            )
            return False
    return True
