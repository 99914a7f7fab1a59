"""Importers: turn sites made with other tools into a ``content/`` tree.

See docs/import-cmsimde.md."""
