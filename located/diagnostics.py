"""Located diagnostics: one record and one line format for every package's input problems.

A teacher fixing a roster, a student fixing a page's front matter and someone loading a scene
all need the same thing: the file, the line, the field, and what is wrong, on one line they can
paste into an editor's "go to". ``roster/``, ``sitegen/`` and ``sims/`` report through this one
type so the three never disagree on field order or on how "the whole file" is written.

The line format (``Diagnostic.format``)::

    file:line: severity: field: message
    file:line:column: severity: field: message   (when a column is known)
    file: severity: field: message               (the file as a whole: line is None)

Everything quoted from input is passed through :func:`printable` first, so a tab, CR or escape
sequence in a roster cell or file name cannot break the one-line form or a terminal.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

Severity = Literal["error", "warning", "info"]

WHOLE_FILE = None
"""The ``line`` of a diagnostic about the file as a whole (unreadable, wrong type, too big)."""

_CONTROL_ESCAPES = {"\t": "\\t", "\n": "\\n", "\r": "\\r"}
_INVISIBLE = "\u2028\u2029\u200b\u200e\u200f\ufeff"


def printable(text: str) -> str:
    """Escape control and line-separator characters so a message stays on one line."""
    out = []
    for ch in text:
        code = ord(ch)
        if ch in _CONTROL_ESCAPES:
            out.append(_CONTROL_ESCAPES[ch])
        elif code < 0x20 or 0x7F <= code < 0xA0 or ch in _INVISIBLE:
            out.append(f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}")
        else:
            out.append(ch)
    return "".join(out)


def quoted(value: str) -> str:
    """Quote a raw input value for a message (single quotes, control chars escaped)."""
    return "'" + printable(value) + "'"


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """One finding about an input file, located precisely enough to fix it.

    ``line`` is 1-based, or ``None`` (:data:`WHOLE_FILE`) for the file as a whole. ``field``
    names the spot inside the line or document: a column (``col 4``), a key path
    (``typos.4823122``), a scene object (``hinge``); it may be empty. ``column`` is 1-based
    and optional (syntax errors know it)."""

    file: str
    line: int | None
    field: str
    message: str
    severity: Severity = "error"
    column: int | None = None

    def format(self) -> str:
        """The one-line ``file:line: severity: field: message`` form."""
        where = printable(self.file)
        if self.line is not None:
            where += f":{self.line}"
            if self.column is not None:
                where += f":{self.column}"
        what = f"{printable(self.field)}: " if self.field else ""
        return f"{where}: {self.severity}: {what}{printable(self.message)}"

    def __str__(self) -> str:
        return self.format()

    def sort_key(self) -> tuple[str, int, int, str]:
        """File, then line (whole-file first), then column, then message."""
        return (self.file, self.line or 0, self.column or 0, self.message)


class LocatedError(Exception):
    """An error that stops a reader, carrying the :class:`Diagnostic` that explains it.

    ``str()`` is the diagnostic's one line, so a command line prints it as is (no traceback).
    Package errors (``roster.RosterError``, ``sims.scene.SceneError``) derive from this."""

    def __init__(self, diagnostic: Diagnostic) -> None:
        self.diagnostic = diagnostic
        super().__init__(diagnostic.format())

    @property
    def file(self) -> str:
        return self.diagnostic.file

    @property
    def line(self) -> int | None:
        return self.diagnostic.line

    @property
    def field(self) -> str:
        return self.diagnostic.field

    @property
    def message(self) -> str:
        return self.diagnostic.message

    def __str__(self) -> str:
        return self.diagnostic.format()
