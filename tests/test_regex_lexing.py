"""Code blocks lexed by sitegen.regex_lexing get exactly Pygments' own tokens.

The shortcut only skips rules that cannot match where the text is (sitegen.regex_starts); a
wrong skip would change a token's type, so every check compares whole token streams (and the
analysis itself against brute force).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pygments.lexer import RegexLexer, bygroups, combined, default, include, this, using, words
from pygments.lexers import find_lexer_class_by_name
from pygments.token import Comment, Keyword, Name, Number, Punctuation, String, Text

from sitegen.regex_lexing import accelerable, accelerate
from sitegen.regex_starts import holds_any, required_needles, start_needles, starts_with

REPO = Path(__file__).resolve().parent.parent

SAMPLES = [
    "",
    "\n",
    "x",
    "import sim as vrep\nclientID = vrep.simxStart('127.0.0.1', 19997, True, True, 5000, 5)\n",
    'f"{a!r:>{w}} {b}" + rb"\\x00" + """doc\n"""  # 註解 中文\n',
    "def 函數(x, *args, **kw):\n    return x @ y if x else [i for i in range(3)]\n",
    "class A(B, metaclass=M):\n    async def f(self): await g(); yield from h()\n",
    "0x1F 0o17 0b101 1_000 1e-3 3.14j .5 5. 1__0\n",
    "int main(void) { /* c */ return 0; } // end\n#include <stdio.h>\n",
    "local t = {1, 2; x = [[long\nstring]]} -- comment\nfunction f(...) end\n",
    "<div class=\"a\" id='b'>&amp; text <!-- c --><script>var x = 1;</script></div>\n",
    'for f in *.md; do echo "$f" ${x:-y} $(date); done # done\n',
    '{"a": [1, 2.5, true, null], "b": {"c": "d\\u00e9"}}\n',
    "SELECT a, COUNT(*) FROM t WHERE x LIKE '%y%' GROUP BY a;\n",
    'unterminated "string and (( brackets {{ \t\r\n\x00 \u212a \u017f \u0130',
    "\t\tmixed   indent\r\n  trailing  \n\n\n",
]
#: The languages a course site's code blocks use, and some with unusual rule sets.
LANGUAGES = [
    "python",
    "python2",
    "pycon",
    "c",
    "cpp",
    "lua",
    "javascript",
    "html",
    "css",
    "bash",
    "console",
    "json",
    "yaml",
    "sql",
    "markdown",
    "ini",
    "diff",
    "matlab",
    "text",
]


def _tokens(lexer, text: str) -> list:
    return list(lexer.get_tokens(text))


def _repo_texts() -> list[str]:
    paths = sorted(REPO.glob("sitegen/*.py"))[:6] + sorted(REPO.glob("templates/*.html"))[:3]
    return [p.read_text(encoding="utf-8")[:4000] for p in paths]


@pytest.mark.parametrize("language", LANGUAGES)
def test_course_languages_lex_to_pygments_tokens(language):
    cls = find_lexer_class_by_name(language)
    stock, fast = cls(), accelerate(cls())
    for text in SAMPLES + _repo_texts():
        assert _tokens(fast, text) == _tokens(stock, text), (language, text[:60])


@pytest.mark.parametrize("level", ["none", "basic", "full"])
def test_lexers_whose_rules_depend_on_options_lex_the_same(level):
    # C# picks its rule table per instance from the unicodelevel option
    cls = find_lexer_class_by_name("csharp")
    stock, fast = cls(unicodelevel=level), accelerate(cls(unicodelevel=level))
    for text in SAMPLES + ["class Ünï { int ñ = 1; } // 中文\n"]:
        assert _tokens(fast, text) == _tokens(stock, text), (level, text[:60])


def test_python_lexer_is_accelerated_and_other_lexers_are_left_alone():
    python = find_lexer_class_by_name("python")()
    assert accelerable(type(python))
    assert "get_tokens_unprocessed" in vars(accelerate(python))
    # an ExtendedRegexLexer finds tokens its own way: not touched
    ruby = find_lexer_class_by_name("ruby")()
    assert not accelerable(type(ruby))
    assert "get_tokens_unprocessed" not in vars(accelerate(ruby))


class Tricky(RegexLexer):
    """Rules that test the analysis: flags per rule, empty matches, state moves, callbacks."""

    name = "tricky"
    flags = re.MULTILINE
    tokens = {
        "root": [
            (r"(?i)select\b", Keyword),  # leading global flag: case-insensitive
            (r"(?<![\w.])k\w*", Name.Builtin),  # lookbehind, then a literal
            (words(("für", "naïve", "ſtraße"), suffix=r"\b"), Keyword.Reserved),
            (r"[^\W\d_]+(?=\()", Name.Function),  # a negated class inside a class
            (r"(\d+)(\.)(\d*)", bygroups(Number, Punctuation, Number)),
            (r"\d+", Number),
            (r"#.*?$", Comment),
            (r"'", String, "string"),
            (r"\{", Punctuation, combined("braces", "string")),
            (r"<", Punctuation, ("angle", "angle")),
            (r"@(\w+)", bygroups(Name.Decorator)),
            (r"`([^`]*)`", bygroups(using(this, state="string"))),  # lexes itself, deeper
            (r"\s+", Text),
            (r"\w+", Name),
        ],
        "string": [
            (r"\\.", String.Escape),
            (r"'", String, "#pop"),
            (r"[^'\\]+", String),
        ],
        "braces": [
            (r"\}", Punctuation, "#pop"),
            (r"(?x) \#push  # verbose, with a comment at the end", Keyword, "#push"),
            include("root"),
        ],
        "angle": [
            (r">>", Punctuation, "#pop:2"),
            (r">", Punctuation, "#pop"),
            (r"(?i:[a-zK])+", Name.Tag),
            default("#pop"),
        ],
    }


TRICKY_TEXTS = [
    "SELECT Select sElEcT selection k9 .k kelvin \u212aelvin für naïve ſtraße STRASSE\n",
    "f(1) 1.5 2. 3 # comment\n'esc\\'aped' {a 'b' #push } <<abc>> <x> <> <Kk\u212a>\n",
    "@deco `inline code` \x00 ~ \u0130 \n\n{ unclosed 'string\nnext line\n",
]


def test_rule_sets_with_flags_empty_matches_and_state_moves_lex_the_same():
    stock, fast = Tricky(), accelerate(Tricky())
    for text in TRICKY_TEXTS + SAMPLES:
        assert _tokens(fast, text) == _tokens(stock, text), text[:60]


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet="Kk\u212aSsſ'\\{}<>@`#.19 \nSELECTfürnaïve(_é", max_size=60))
def test_any_text_lexes_the_same_with_tricky_rules(text):
    assert _tokens(accelerate(Tricky()), text) == _tokens(Tricky(), text)


@settings(max_examples=150, deadline=None)
@given(st.text(alphabet="def(x):\n 'f\"{}[]#0x1.e\\@*=-\u212a中", max_size=80))
def test_any_text_lexes_the_same_as_python(text):
    cls = find_lexer_class_by_name("python")
    assert _tokens(accelerate(cls()), text) == _tokens(cls(), text)


#: Patterns for the analysis: classes, categories, case folding beyond ASCII, assertions,
#: repeats that may be empty, alternatives, scoped flags.
PATTERNS = [
    r"abc",
    r"(?i)k",
    r"(?i)[a-c]x",
    r"(?i)[^a]",
    r"\d+",
    r"\D",
    r"\w+\s",
    r"[^\W\d]",
    r"(?<!\\)`+",
    r"(?=x)\w",
    r"a*b",
    r"(?:a|b?)c",
    r"(?i:ſ)",
    r"x{0}y",
    r"(a)\1",
    r"$",
    r"\b",
    r"(?s).",
    r"[\u0100-\u0200]z",
    r"(?i)[\u2100-\u2200]",  # holds the Kelvin sign, which folds to k
    r"(?i)\u212a|\u017f",
    r"[a-f\d]+|[^\x00-\x40]",
    r"(a)?(?(1)b|c)",  # a construct the analysis does not read: may start anywhere
]
if sys.version_info >= (3, 11):  # atomic groups and possessive repeats came with 3.11
    PATTERNS += [r"(?>ab|c)", r"a++b"]
CHARS = "abcxyzkKs1٣_ \t\n\\`\u212aſ\u0130\u0101é中\x00"


@pytest.mark.parametrize("source", PATTERNS)
def test_a_character_said_not_to_start_a_match_never_does(source):
    pattern = re.compile(source)
    test = starts_with(pattern)
    for ch in CHARS:
        for rest in ("", "a", "b", "c", "x", "y", "z", "bc", "ab", "1", " ", "`", ch):
            if pattern.match(ch + rest) is not None:
                assert test(ch), (source, ch, rest)
    if pattern.match("") is not None:
        assert test("")


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet=CHARS + "!&*<[]^:|>#- \n", max_size=30))
def test_a_text_without_the_needles_holds_no_match(text):
    inline = [
        re.compile(p)
        for p in (r"\\(.)", r"\[\^([^\]]*)\]", r"(?<!\!)\[", r"  \n", r"\*|_", r"(&[a-z]+;)")
    ]
    if any(p.search(text) for p in inline):
        assert holds_any(start_needles(inline) or ("",))(text), text
    blocks = PATTERNS + [r"(?:^|\n)!!! ?x", r"^[ ]{0,3}(?=(-+ ?){3,})(-+)$", r"(^|\n)[ ]{0,3}:"]
    for source in blocks:
        pattern = re.compile(source, re.M)
        if pattern.search(text):
            assert holds_any(required_needles(pattern) or ("",))(text), (source, text)


def test_needles_keep_literal_starts_whole_and_are_none_when_unsure():
    assert start_needles([re.compile(r"  \n")]) == ("  \n",)
    assert start_needles([re.compile(r"\*|_"), re.compile(r"(&x;)")]) == ("&", "*", "_")
    assert start_needles([re.compile(r"&x;"), re.compile(r"&")]) == ("&",)
    assert start_needles([re.compile(r"a?")]) is None  # may match the empty string
    assert start_needles([re.compile(r"\w")]) is None  # may start beyond ASCII
    assert start_needles([re.compile(r"(?i)k")]) is None  # the Kelvin sign folds to k
    assert required_needles(re.compile(r"(?:^|\n)!!! ?x")) == ("!!!",)
    # what a lookahead must see counts, the fewest strings win
    assert required_needles(re.compile(r"^ ?(?=(-+ ?){3,}|(_+ ?){3,})[-_ ]+$")) == ("-", "_")
    assert required_needles(re.compile(r"a?b?")) is None
