"""The theme's Jinja2 environment, with attributes of plain dicts looked up directly.

Templates read page data as attributes (``page.title``, ``t.copy_code``, ``crumb.url``), and
sitegen hands them plain dicts. Jinja2 answers ``obj.name`` by trying Python's ``getattr``
first and the item second, so every such look-up on a dict raised and caught an
``AttributeError``: about a hundred per page, a third of rendering a page's template.

A plain ``dict`` has no attributes but its class's (it has no instance ``__dict__``), so for
any name that is not one of those, ``getattr`` is known to fail: :class:`ThemeEnvironment` goes
straight to the item, as Jinja2 would after the failure. Names ``dict`` does have (``items``,
``keys``), other types and missing keys take Jinja2's own path, so every template renders
exactly as before (``tests/test_theme_env.py``).
"""

from __future__ import annotations

from typing import Any

import jinja2

#: What ``getattr`` finds on a plain dict: the names of its class (and ``object``'s).
_DICT_ATTRIBUTES = frozenset(dir(dict))


class ThemeEnvironment(jinja2.Environment):
    """``jinja2.Environment`` with :meth:`getattr` going straight to a plain dict's item."""

    def getattr(self, obj: Any, attribute: str) -> Any:
        if type(obj) is dict and attribute not in _DICT_ATTRIBUTES:
            try:
                return obj[attribute]
            except (TypeError, LookupError):
                return self.undefined(obj=obj, name=attribute)
        return super().getattr(obj, attribute)
