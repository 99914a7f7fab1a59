"""Importers: turn sites made with other tools into a ``content/`` tree (see docs/README-import.md)."""
