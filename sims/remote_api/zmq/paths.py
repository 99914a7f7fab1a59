"""Object paths for ZeroMQ clients: the one resolver of the project, ``sims.scene.paths`` (the
Lua scripts and the legacy API use it too). Kept as a module name for the server's imports."""

from sims.scene.paths import (
    Entry,
    PathError,
    Tree,
    alias_of,
    full_path,
    is_path,
    nearest,
    parse,
    resolve,
    resolve_name,
)

__all__ = [
    "Entry",
    "PathError",
    "Tree",
    "alias_of",
    "full_path",
    "is_path",
    "nearest",
    "parse",
    "resolve",
    "resolve_name",
]
