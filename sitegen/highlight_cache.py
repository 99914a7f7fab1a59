"""Highlighted code blocks kept by content, so Pygments lexes a block once, not once per build.

Pygments is a large share of converting a page that has code, and the first block of a
language in a process also pays for compiling that lexer's rules (~50-90 ms for Python). A
block's HTML depends only on its text, its lexer (class and options) and the formatter's
options, so it is kept under the hash of those:

* in memory, for the rest of the process (a snippet repeated on several pages is highlighted
  once; a small bounded table, so memory does not grow with the site);
* in the fragment store between builds (:mod:`sitegen.fragment_store`), so a page whose prose
  was edited is converted again without lexing its unchanged code, and without compiling a
  lexer at all: codehilite is handed a :class:`LazyLexer`, which makes the real lexer only
  when a block must really be highlighted.

The output is byte-identical to calling Pygments every time (``tests/test_highlight_cache.py``).
"""

from __future__ import annotations

import functools
import hashlib
from collections import OrderedDict
from collections.abc import Callable
from typing import Any

import pygments

#: Blocks remembered in memory per process (the store keeps all of them between builds).
MEMO_SIZE = 512


class LazyLexer:
    """A lexer's class and options, standing in for the lexer until a block needs lexing
    (Pygments compiles a lexer class's rules when the first instance is made)."""

    def __init__(self, cls: type, options: dict[str, Any]):
        self.cls = cls
        self.options = options
        self.name = cls.name
        self.aliases = cls.aliases
        self.key = f"{cls.__module__}.{cls.__qualname__}:{sorted(options.items())!r}"
        self._lexer: Any = None

    def lexer(self) -> Any:
        if self._lexer is None:
            # the same tokens for fewer regex calls; imported here: most builds lex nothing
            from sitegen.regex_lexing import accelerate

            self._lexer = accelerate(self.cls(**self.options))
        return self._lexer

    def get_tokens(self, text: str, unfiltered: bool = False) -> Any:
        """What Pygments asks a lexer for, so the stand-in works wherever a lexer does."""
        return self.lexer().get_tokens(text, unfiltered)


class HighlightCache:
    """``block key -> HTML``: a bounded memo in front of an optional lookup (the store)."""

    def __init__(self) -> None:
        self.memo: OrderedDict[str, str] = OrderedDict()
        #: key -> HTML of blocks highlighted in this process and not yet handed to the store
        self.new: dict[str, str] = {}
        #: keys of every block looked up since the last :meth:`take_used` (cache pruning)
        self.used: list[str] = []
        #: the store's lookup, set by the Markdown stage when a store with blocks exists
        self.lookup: Callable[[str], str | None] | None = None

    @functools.cached_property
    def code(self) -> str:
        """The code that highlights (Pygments, our lexing and rendering modules) as
        :mod:`located.code_keys` keys it: part of every block's key."""
        from located.code_keys import code_key

        return code_key("sitegen.markdown_render")

    def highlight(self, src: str, lexer: Any, formatter: Any) -> str:
        """``pygments.highlight(src, lexer, formatter)``, from the cache when it has it (only
        blocks of a :class:`LazyLexer`, whose key names its class and options, are kept)."""
        if not isinstance(lexer, LazyLexer):
            return pygments.highlight(src, lexer, formatter)
        form_key = repr(sorted(formatter.options.items()))
        key = hashlib.sha256(f"{self.code}\0{lexer.key}\0{form_key}\0{src}".encode()).hexdigest()
        self.used.append(key)
        html = self.memo.get(key)
        if html is not None:
            self.memo.move_to_end(key)
            self.new[key] = html  # the store in use may not have it (another site's build)
            return html
        if self.lookup is not None:
            html = self.lookup(key)
        if html is None:
            html = pygments.highlight(src, lexer.lexer(), formatter)
            self.new[key] = html
        self.memo[key] = html
        if len(self.memo) > MEMO_SIZE:
            self.memo.popitem(last=False)
        return html

    def take_new(self) -> dict[str, str]:
        new, self.new = self.new, {}
        return new

    def take_used(self) -> list[str]:
        used, self.used = self.used, []
        return used


#: The process's cache (one per process: forked workers start from the build's copy).
BLOCKS = HighlightCache()
