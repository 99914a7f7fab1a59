"""Pygments' regex lexers, trying at each position only the rules that can match there.

A Pygments ``RegexLexer`` finds each token by trying its current state's rules one by one
(``rule.match(text, pos)`` until one matches): for Python source about thirty calls per token,
most of them rules that cannot match the character at ``pos`` at all (a keyword rule at a
digit, a string rule at a letter). That made lexing most of the time spent on code blocks.

Here each rule's pattern is read once (:mod:`sitegen.regex_starts`) to know which characters
a match of it can start with. For each state and character met, the state's rules that can
match there, kept in their order, are worked out once; at each position only those are tried.
A rule that may match the empty string is tried everywhere. The first rule that matches wins,
as in Pygments, so the tokens are exactly Pygments' own (``tests/test_regex_lexing.py``
compares them): a rule left out is one that cannot match at that position, and where the
analysis is unsure it keeps the rule, which only costs speed. Lexers that replace
``get_tokens_unprocessed`` (``ExtendedRegexLexer``, wrappers) are left alone.
"""

from __future__ import annotations

import re
import types
from collections.abc import Iterator
from typing import Any

from pygments.lexer import RegexLexer
from pygments.token import Error, Whitespace, _TokenType

from sitegen.regex_starts import starts_with

#: id(rule table) -> (the table, state -> character -> the state's rules that can match
#: there, in order). Keyed by the table, not the class: a lexer may pick its rules by its
#: options (C#'s ``unicodelevel``); the table is kept so that its id stays its own.
_CANDIDATES: dict[int, tuple[dict, dict[str, dict[str, tuple]]]] = {}


def _tables(tokendefs: dict) -> dict[str, dict[str, tuple]]:
    entry = _CANDIDATES.get(id(tokendefs))
    if entry is None or entry[0] is not tokendefs:
        entry = _CANDIDATES[id(tokendefs)] = (tokendefs, {})
    return entry[1]


def _rules_at(tokendefs: dict, state: str, ch: str) -> tuple:
    """The rules of ``state`` that can match where the text continues with ``ch``."""
    table = _tables(tokendefs).setdefault(state, {})
    rules = table.get(ch)
    if rules is None:
        rules = table[ch] = tuple(
            rule
            for rule in tokendefs[state]
            if not isinstance(getattr(rule[0], "__self__", None), re.Pattern)
            or starts_with(rule[0].__self__)(ch)
        )
    return rules


def prepare(lexer: Any) -> None:
    """Read every rule's pattern of ``lexer`` now: before workers are forked, so each inherits
    the analysis instead of making it again."""
    if accelerable(type(lexer)):
        for rules in lexer._tokens.values():
            for rule in rules:
                if isinstance(getattr(rule[0], "__self__", None), re.Pattern):
                    starts_with(rule[0].__self__)


def accelerable(cls: type) -> bool:
    """Whether lexers of ``cls`` find tokens with Pygments' own ``RegexLexer`` loop."""
    return (
        isinstance(cls, type)
        and issubclass(cls, RegexLexer)
        and cls.get_tokens_unprocessed is RegexLexer.get_tokens_unprocessed
    )


def accelerate(lexer: Any) -> Any:
    """``lexer`` with its tokens found by :func:`tokens_unprocessed` (when it is a plain regex
    lexer; any other lexer is returned as it is)."""
    if accelerable(type(lexer)):
        lexer.get_tokens_unprocessed = types.MethodType(tokens_unprocessed, lexer)
    return lexer


def tokens_unprocessed(
    self: RegexLexer, text: str, stack: tuple[str, ...] = ("root",)
) -> Iterator[tuple[int, Any, str]]:
    """``RegexLexer.get_tokens_unprocessed`` trying only the rules that can match at each
    position (see the module's docstring); the state handling is Pygments' own, step for
    step."""
    tokendefs = self._tokens
    tables = _tables(tokendefs)
    pos = 0
    end = len(text)
    statestack = list(stack)
    state = statestack[-1]
    table = tables.setdefault(state, {})
    while 1:
        ch = text[pos] if pos < end else ""
        rules = table.get(ch)
        if rules is None:
            rules = _rules_at(tokendefs, state, ch)
        for rexmatch, action, new_state in rules:
            m = rexmatch(text, pos)
            if m:
                if action is not None:
                    if type(action) is _TokenType:
                        yield pos, action, m.group()
                    else:
                        yield from action(self, m)
                pos = m.end()
                if new_state is not None:
                    if isinstance(new_state, tuple):
                        for name in new_state:
                            if name == "#pop":
                                if len(statestack) > 1:
                                    statestack.pop()
                            elif name == "#push":
                                statestack.append(statestack[-1])
                            else:
                                statestack.append(name)
                    elif isinstance(new_state, int):
                        # pop, but keep at least one state on the stack
                        if abs(new_state) >= len(statestack):
                            del statestack[1:]
                        else:
                            del statestack[new_state:]
                    elif new_state == "#push":
                        statestack.append(statestack[-1])
                    else:
                        raise AssertionError(f"wrong state def: {new_state!r}")
                    state = statestack[-1]
                    table = tables.setdefault(state, {})
                break
        else:  # no rule matched
            if pos >= end:
                break
            if text[pos] == "\n":  # at the end of a line, back to "root"
                statestack = ["root"]
                state = "root"
                table = tables.setdefault(state, {})
                yield pos, Whitespace, "\n"
            else:
                yield pos, Error, text[pos]
            pos += 1
