"""What a match of a regular expression can start with, and what every match must hold.

Two hot loops of a build try many regular expressions where most of them cannot match:
Pygments' regex lexers (:mod:`sitegen.regex_lexing`) and Python-Markdown's inline patterns and
block tests (:mod:`sitegen.markdown_speed`). Knowing from a pattern alone which characters its
matches can start with lets them skip those calls without changing any result.

A pattern is read once with Python's own regular-expression parser (``re._parser``;
``sre_parse`` on Python 3.10), so it is read exactly as ``re`` reads it, and its *first
characters* are worked out in one pass: the ASCII characters a match may start with, and
whether it may start with any character beyond ASCII. The answer errs one way only: whatever
is unsure (a construct not known here, case-insensitive matching beyond ASCII, a negated class
under ``IGNORECASE``) counts as "may start here", which costs speed, never a match.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from typing import Any

try:  # Python 3.11+
    from re import _constants as sre
    from re import _parser as sre_parse
except ImportError:  # Python 3.10
    import sre_constants as sre  # type: ignore[no-redef]
    import sre_parse  # type: ignore[no-redef]

_REPEATS = {
    op
    for op in (sre.MAX_REPEAT, sre.MIN_REPEAT, getattr(sre, "POSSESSIVE_REPEAT", None))
    if op is not None
}
_ATOMIC = getattr(sre, "ATOMIC_GROUP", None)
_ONE_CHAR = {sre.LITERAL, sre.NOT_LITERAL, sre.ANY, sre.IN}
_ZERO_WIDTH = {sre.AT, sre.ASSERT, sre.ASSERT_NOT}  # assertions only narrow a match: ignored
_ASCII = frozenset(map(chr, range(128)))
#: A class's category -> the ASCII characters in it (str patterns: the Unicode categories).
_CATEGORY = {
    category: frozenset(c for c in _ASCII if re.match(pattern, c))
    for category, pattern in (
        (sre.CATEGORY_DIGIT, r"\d"),
        (sre.CATEGORY_NOT_DIGIT, r"\D"),
        (sre.CATEGORY_SPACE, r"\s"),
        (sre.CATEGORY_NOT_SPACE, r"\S"),
        (sre.CATEGORY_WORD, r"\w"),
        (sre.CATEGORY_NOT_WORD, r"\W"),
    )
}
#: "May start with anything": the answer for whatever is not known.
_ANYTHING = (_ASCII, True)

#: First characters: (the ASCII characters a match may start with, whether it may start with
#: a character beyond ASCII).
Firsts = tuple[frozenset[str], bool]

_TESTS: dict[re.Pattern, Callable[[str], bool]] = {}


def starts_with(pattern: re.Pattern) -> Callable[[str], bool]:
    """``ch -> bool``: False only when no match of ``pattern`` can start with the character
    ``ch``. ``""`` stands for the end of the text (only a pattern that may match the empty
    string matches there)."""
    test = _TESTS.get(pattern)
    if test is None:
        try:
            tree, icase = _parse(pattern)
            nullable = _nullable(tree)
            ascii_chars, beyond = _first_of_sequence(tree, icase)

            def test(ch: str) -> bool:
                if nullable:
                    return True
                return ch in ascii_chars if ch.isascii() else beyond

        except Exception:  # anything unexpected: the pattern may match anywhere

            def test(ch: str) -> bool:
                return True

        _TESTS[pattern] = test
    return test


def start_needles(patterns: Iterable[re.Pattern]) -> tuple[str, ...] | None:
    """Strings one of which a text holds wherever a match of any of ``patterns`` starts, or
    None when not known (a pattern may match the empty string, start beyond ASCII, or is
    case-insensitive). A literal start of two or more characters is one string (``"  \\n"``),
    which is found in far fewer texts than its first character."""
    chars: set[str] = set()
    leads: set[str] = set()
    try:
        for pattern in patterns:
            tree, icase = _parse(pattern)
            if icase or _nullable(tree):
                return None
            lead = ""
            for op, av in tree:  # literals at the very start (no assertion before them)
                if op is not sre.LITERAL:
                    break
                lead += chr(av)
            if len(lead) >= 2:
                leads.add(lead)
                continue
            first, beyond = _first_of_sequence(tree, False)
            if beyond:
                return None
            chars.update(first)
    except Exception:
        return None
    return tuple(sorted(chars)) + tuple(sorted(lead for lead in leads if lead[0] not in chars))


def required_needles(pattern: re.Pattern) -> tuple[str, ...] | None:
    """Strings one of which every match of ``pattern`` holds (its fewest such, from one of the
    parts every match has), or None when not known. A text holding none of them holds no
    match: ``pattern.search`` would find nothing."""
    try:
        tree, icase = _parse(pattern)
        return None if icase else _sequence_needles(list(tree))
    except Exception:
        return None


def holds_any(needles: tuple[str, ...]) -> Callable[[str], bool]:
    """``text -> bool``: whether ``text`` holds one of ``needles`` (a substring test each:
    several times faster than a regular expression over the same characters)."""

    def holds(text: str) -> bool:
        for needle in needles:
            if needle in text:
                return True
        return False

    return holds


def _parse(pattern: re.Pattern) -> tuple[Any, bool]:
    if not isinstance(pattern.pattern, str) or pattern.flags & (re.ASCII | re.LOCALE):
        raise ValueError("not analysed")
    return sre_parse.parse(pattern.pattern, pattern.flags), bool(pattern.flags & re.IGNORECASE)


def _sequence_needles(items: list) -> tuple[str, ...] | None:
    best = None
    for at, (op, av) in enumerate(items):
        if op is sre.ASSERT:  # what a lookahead or lookbehind must see is in the text too
            found = _sequence_needles(list(av[1]))
        elif _nullable_item(op, av):
            continue
        else:
            found = _item_needles(items, at)
        if found is not None and (best is None or len(found) < len(best)):
            best = found
    return best


def _item_needles(items: list, at: int) -> tuple[str, ...] | None:
    """What a match of ``items[at]`` (not nullable) starts with: the run of literals from
    there when it is two or more long, else the ASCII characters it may start with (None if
    it may start beyond ASCII)."""
    lead = ""
    for op, av in items[at:]:
        if op is not sre.LITERAL:
            break
        lead += chr(av)
    if len(lead) >= 2:
        return (lead,)
    first, beyond = _first_of_item(*items[at], False)
    return None if beyond else tuple(sorted(first))


def _nullable(items: Any) -> bool:
    """Whether the sequence ``items`` may match the empty string (unknown: True)."""
    return all(_nullable_item(op, av) for op, av in items)


def _nullable_item(op: Any, av: Any) -> bool:
    if op in _ONE_CHAR:
        return False
    if op is sre.BRANCH:
        return any(_nullable(branch) for branch in av[1])
    if op is sre.SUBPATTERN:
        return _nullable(av[3])
    if op is _ATOMIC:
        return _nullable(av)
    if op in _REPEATS:
        return av[0] == 0 or av[1] == 0 or _nullable(av[2])
    return True  # assertions (zero width) and anything not known


def _first_of_sequence(items: Any, icase: bool) -> Firsts:
    """The first characters of a match of the sequence ``items``: those of its first item,
    and of the next ones while the ones before may match the empty string."""
    chars: frozenset[str] = frozenset()
    beyond = False
    for op, av in items:
        first, more = _first_of_item(op, av, icase)
        chars, beyond = chars | first, beyond or more
        if not _nullable_item(op, av):
            break
    return chars, beyond


def _first_of_item(op: Any, av: Any, icase: bool) -> Firsts:
    if op is sre.LITERAL:
        return _first_of_literal(chr(av), icase)
    if op is sre.NOT_LITERAL:
        return (_ASCII, True) if icase else (_ASCII - {chr(av)}, True)
    if op is sre.IN:
        return _first_of_class(av, icase)
    if op is sre.BRANCH:
        chars: frozenset[str] = frozenset()
        beyond = False
        for branch in av[1]:
            first, more = _first_of_sequence(branch, icase)
            chars, beyond = chars | first, beyond or more
        return chars, beyond
    if op is sre.SUBPATTERN:
        _group, add, remove, sub = av
        if add & re.IGNORECASE:
            icase = True
        if remove & re.IGNORECASE:
            icase = False
        return _first_of_sequence(sub, icase)
    if op is _ATOMIC:
        return _first_of_sequence(av, icase)
    if op in _REPEATS:
        return (frozenset(), False) if av[1] == 0 else _first_of_sequence(av[2], icase)
    if op in _ZERO_WIDTH:
        return frozenset(), False
    return _ANYTHING  # ANY and anything not known


def _first_of_literal(ch: str, icase: bool) -> Firsts:
    if not icase:
        return (frozenset(ch), False) if ch.isascii() else (frozenset(), True)
    if not ch.isascii() or not ch.isalpha():  # Unicode case folding has odd pairs (K, k)
        return _ANYTHING if ch.isalpha() or not ch.isascii() else (frozenset(ch), False)
    return frozenset({ch, ch.lower(), ch.upper()}), True


def _first_of_class(items: list, icase: bool) -> Firsts:
    negate = bool(items) and items[0][0] is sre.NEGATE
    if negate and icase:
        return _ANYTHING
    chars: set[str] = set()
    beyond = False
    for op, av in items:
        if op is sre.NEGATE:
            continue
        if op is sre.LITERAL:
            first, more = _first_of_literal(chr(av), icase)
        elif op is sre.RANGE:
            low, high = av
            if icase and high > 127:  # may hold a character that folds to ASCII (K, k)
                return _ANYTHING
            first = frozenset(map(chr, range(low, min(high, 127) + 1)))
            more = high > 127
            if icase:
                first = first | {c.swapcase() for c in first if c.isalpha()}
                more = more or any(c.isalpha() for c in first)
        elif op is sre.CATEGORY and av in _CATEGORY:
            first, more = _CATEGORY[av], True
        else:
            return _ANYTHING
        chars |= first
        beyond = beyond or more
    if negate:  # the members were read exactly (no case folding), so the rest is exact
        return _ASCII - chars, True
    return frozenset(chars), beyond
