"""Roster YAML (rosters and corrections) through the shared line-numbered walker.

`yaml.safe_load` throws line numbers away and turns `0123` or `40823131` into
ints; composing instead keeps each scalar's exact text and `start_mark`, which
is what error messages and "correction applied at line N" reports need. The
walking itself is `located.yamlwalk.Walker` (shared with `sitegen.yml`); here it
reports into the roster's `Collector` and refuses anchors/aliases, which in a
roster would silently count one student twice.
"""

from __future__ import annotations

from located import yaml as located_yaml
from located.yamlwalk import ROOT, Node, describe, line_of
from located.yamlwalk import Walker as _Walker

from .records import Collector

__all__ = ["ROOT", "Node", "Walker", "compose", "describe", "line_of"]


def compose(text: str, c: Collector) -> Node | None:
    """Compose one YAML document through the shared bounded loader (``located.yaml``:
    limits on size, aliases, expansion and depth), reporting errors at their line."""
    try:
        return located_yaml.compose(text, c.file)
    except located_yaml.YamlError as exc:
        c.error(exc.line or 1, f"char {exc.column}" if exc.column else "file", exc.message)
    return None


class Walker(_Walker):
    """The shared walker, reporting into a Collector's diagnostics (``c``), aliases refused."""

    def __init__(self, c: Collector) -> None:
        super().__init__(c.file, c.diagnostics, aliases=False)
        self.c = c
