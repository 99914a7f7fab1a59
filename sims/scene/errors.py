"""The one error a scene reader raises: located by file and object, shown as one line."""

from __future__ import annotations

from located.diagnostics import Diagnostic, LocatedError


class SceneError(LocatedError):
    """A scene file that cannot be read. ``obj`` names the object (or part of the file, such as
    "header") where reading stopped; ``line`` is the file line when the format has lines (XML).
    ``str()`` is the shared located line (``located.diagnostics``) the command line prints:
    ``file: error: object: message``, or ``file:line: error: object: message``."""

    def __init__(self, file: str, obj: str, message: str, line: int | None = None):
        super().__init__(Diagnostic(str(file), line, obj, message))
        self.obj = obj
