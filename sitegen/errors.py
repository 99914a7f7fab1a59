"""Diagnostics: one clear line per problem, naming file, line and field.

The record itself is :class:`located.diagnostics.Diagnostic` (shared with ``roster/`` and
``sims/``), re-exported here because every sitegen module imports it from this place.

Every stage reports through :class:`Diagnostics` instead of raising, so that one bad page
does not hide the others; :class:`BuildError` stops a build and is turned into exit code 1
by the CLI, never into a traceback.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from located.diagnostics import Diagnostic

__all__ = ["BuildError", "Diagnostic", "Diagnostics"]


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

    def add(self, diagnostic: Diagnostic) -> None:
        self.items.append(diagnostic)

    def extend(self, other: list[Diagnostic]) -> None:
        self.items.extend(other)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.items if d.severity == "error"]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.items if d.severity == "warning"]
