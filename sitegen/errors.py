"""Diagnostics: one clear line per problem, naming file, line and field.

Every stage reports through :class:`Diagnostics` instead of raising, so that one bad page
does not hide the others; :class:`BuildError` stops a build and is turned into exit code 1
by the CLI, never into a traceback.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True, order=True)
class Diagnostic:
    """A problem found in the user's input."""

    file: str
    line: int | None
    field: str
    message: str
    severity: str = "error"  # "error" | "warning"

    def __str__(self) -> str:
        where = self.file if self.line is None else f"{self.file}:{self.line}"
        what = f"{self.field}: " if self.field else ""
        return f"{where}: {self.severity}: {what}{self.message}"


class BuildError(Exception):
    """Raised to stop a command; carries the diagnostics that explain why."""

    def __init__(self, message: str, diagnostics: list[Diagnostic] | None = None):
        super().__init__(message)
        self.diagnostics = diagnostics or []


@dataclass
class Diagnostics:
    """Collects errors and warnings in the order they were found."""

    items: list[Diagnostic] = field(default_factory=list)

    def error(self, file: str, line: int | None, fld: str, message: str) -> None:
        self.items.append(Diagnostic(file, line, fld, message, "error"))

    def warning(self, file: str, line: int | None, fld: str, message: str) -> None:
        self.items.append(Diagnostic(file, line, fld, message, "warning"))

    def extend(self, other: list[Diagnostic]) -> None:
        self.items.extend(other)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.items if d.severity == "error"]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.items if d.severity == "warning"]
