"""docs/DESIGN.md is the contract between the packages: everything it names must exist.

The contract drifted before (a ``VirtualPage`` no code had, a theme package under the wrong
name), and a newcomer believes the document first. So this test reads it the way a newcomer
would and checks what it shows:

- every ``from X import A`` / ``import X`` in a ```python block imports;
- every dotted name of ours (``roster.diff``, ``sims.scene.load.load_scene``) in a ```python
  block or a `backtick span` resolves to a module or an attribute;
- a record shown with its fields (``Group(name, slug, leader, members, line)``) has exactly
  those leading fields in that order, and every ``keyword=`` shown is a real parameter;
- every file path of ours in a backtick span (``sims/remote_api/isolate.py``) exists.
"""

from __future__ import annotations

import importlib
import inspect
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DESIGN = ROOT / "docs" / "DESIGN.md"
OURS = ("located", "roster", "sims", "sitegen")

_ALT = "|".join(OURS)
_DOTTED = re.compile(rf"(?<![\w./])((?:{_ALT})(?:\.[A-Za-z_]\w*)+)")
_PATH = re.compile(rf"^(?:{_ALT}|templates|tests|docs|data|bench)/[\w./*-]*$")
_FILE_SUFFIXES = ("py", "md", "yml", "yaml", "json", "html", "toml", "txt")
_CALL = re.compile(r"\b([A-Za-z_][\w.]*)\(([^()]*(?:\([^()]*\)[^()]*)*)\)")


def _text() -> str:
    return DESIGN.read_text(encoding="utf-8")


def python_blocks(text: str) -> list[tuple[int, str]]:
    """(first line, code) of each ```python block."""
    blocks = []
    for m in re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M):
        blocks.append((text[: m.start()].count("\n") + 2, m.group(1)))
    return blocks


def backtick_spans(text: str) -> list[tuple[int, str]]:
    """(line, span) of each `inline code` span outside fenced blocks."""
    spans = []
    fenced = False
    for number, line in enumerate(text.splitlines(), 1):
        if line.startswith("```"):
            fenced = not fenced
            continue
        if not fenced:
            spans += [(number, m.group(1)) for m in re.finditer(r"`([^`]+)`", line)]
    return spans


def resolve(dotted: str) -> object:
    """The module or attribute a dotted name names; raises if there is none."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ModuleNotFoundError as exc:
            if exc.name is not None and not ".".join(parts[:cut]).startswith(exc.name):
                raise  # the module exists but imports something missing
            continue
        for attr in parts[cut:]:
            if not hasattr(obj, attr):
                raise AttributeError(f"{'.'.join(parts[:cut])} has no {attr!r} (in {dotted})")
            obj = getattr(obj, attr)
        return obj
    raise ModuleNotFoundError(dotted)


def _strip_comment(line: str) -> str:
    return line.split("#", 1)[0]


def _split_args(args: str) -> list[str]:
    """Top-level comma-separated parts of an argument list."""
    parts, depth, current = [], 0, ""
    for ch in args:
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append(current.strip())
            current = ""
        else:
            current += ch
    if current.strip():
        parts.append(current.strip())
    return parts


def check_call(name: str, args: str, obj: object) -> list[str]:
    """Problems with ``name(args)`` as shown, against the real signature of ``obj``."""
    try:
        params = list(inspect.signature(obj).parameters.values())
    except (TypeError, ValueError):
        return []
    names = [p.name for p in params]
    takes_kwargs = any(p.kind is p.VAR_KEYWORD for p in params)
    problems = []
    for position, part in enumerate(_split_args(args)):
        m = re.match(r"^([A-Za-z_]\w*)\s*(=|:|$)", part)
        if m is None:
            continue
        word, sep = m.groups()
        if sep == "=":
            if word not in names and not takes_kwargs:
                problems.append(f"{name}(): no parameter {word!r} (has {', '.join(names)})")
        elif inspect.isclass(obj) and (position >= len(names) or names[position] != word):
            problems.append(f"{name}(): field {position + 1} is shown as {word!r}; the fields are")
            problems[-1] += f" {', '.join(names)}"
            break
    return problems


def contract_problems(text: str) -> list[str]:
    problems: list[str] = []
    imported: dict[str, object] = {}
    for first, code in python_blocks(text):
        imported["__modules__"] = []  # modules this block imports from: where bare names live
        for offset, raw in enumerate(code.splitlines()):
            line, where = _strip_comment(raw), f"DESIGN.md:{first + offset}"
            m = re.match(r"^\s*from\s+([\w.]+)\s+import\s+(.+)$", line)
            if m:
                imported["__modules__"].append(m.group(1))
                for name in (n.strip() for n in m.group(2).split(",")):
                    try:
                        imported[name] = resolve(f"{m.group(1)}.{name}")
                    except (ImportError, AttributeError) as exc:
                        problems.append(f"{where}: from {m.group(1)} import {name}: {exc}")
                continue
            m = re.match(r"^\s*import\s+([\w.]+)\s*$", line)
            if m:
                try:
                    importlib.import_module(m.group(1))
                except ImportError as exc:
                    problems.append(f"{where}: import {m.group(1)}: {exc}")
                continue
            problems += _check_names(line, where, imported)
    imported["__modules__"] = []  # bare names in prose are not looked up: qualify them
    for number, span in backtick_spans(text):
        where = f"DESIGN.md:{number}"
        if _PATH.match(span) and "*" not in span:
            if not (ROOT / span.rstrip("/")).exists():
                problems.append(f"{where}: `{span}` does not exist")
            continue
        problems += _check_names(span, where, imported)
    return problems


def _check_names(line: str, where: str, imported: dict[str, object]) -> list[str]:
    problems = []
    for dotted in _DOTTED.findall(line):
        if dotted.rpartition(".")[2] in _FILE_SUFFIXES:
            continue  # a file name such as sitegen.yml is not a dotted name
        try:
            resolve(dotted)
        except (ImportError, AttributeError) as exc:
            problems.append(f"{where}: {dotted}: {exc}")
    for name, args in _CALL.findall(line):
        head, _, rest = name.partition(".")
        if head in imported:
            obj: object = imported[head]
            try:
                for attr in rest.split(".") if rest else []:
                    obj = getattr(obj, attr)
            except AttributeError:
                problems.append(f"{where}: {name}: no such attribute")
                continue
        elif head in OURS:
            try:
                obj = resolve(name)
            except (ImportError, AttributeError):
                continue  # reported above as a dotted name
        elif not rest and name[:1].isupper() and imported.get("__modules__"):
            found = [m for m in imported["__modules__"] if hasattr(resolve(m), name)]
            if not found:
                problems.append(f"{where}: {name} is in none of {imported['__modules__']}")
                continue
            obj = getattr(resolve(found[0]), name)
        else:
            continue
        problems += [f"{where}: {p}" for p in check_call(name, args, obj)]
    return problems


def test_the_checker_catches_each_kind_of_untruth():
    """The test's own reading: each kind of drift it exists for is reported."""
    bad = (
        "```python\n"
        "from roster import load_roster, NoSuchThing\n"
        "import sims.no_such_module\n"
        "roster.no_such_function(x)\n"
        "from roster import Group\n"
        "Group(slug, name, leader, members, line)\n"
        "load_roster(path, no_such_option=1)\n"
        "```\n"
        "Pages come from `sitegen.pages.VirtualPage(rel_path, title)`; see `sims/nope.py`.\n"
    )
    found = "\n".join(contract_problems(bad))
    for expected in (
        "NoSuchThing",
        "sims.no_such_module",
        "roster.no_such_function",
        "field 1 is shown as 'slug'",
        "no parameter 'no_such_option'",
        "VirtualPage",
        "`sims/nope.py` does not exist",
    ):
        assert expected in found, (expected, found)
    good = "```python\nfrom roster import Group\nGroup(name, slug, leader, members, line)\n```\n"
    assert contract_problems(good) == []


def test_design_md_names_only_what_exists():
    if not DESIGN.exists():
        pytest.fail("docs/DESIGN.md is missing")
    problems = contract_problems(_text())
    assert not problems, "docs/DESIGN.md is untrue:\n" + "\n".join(problems)


def test_pyproject_names_only_existing_tests():
    """Comments in pyproject.toml that point at a test must point at one that exists."""
    text = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    for path in re.findall(r"tests/[\w/]+\.py", text):
        assert (ROOT / path).is_file(), f"pyproject.toml names {path}, which does not exist"


def test_lowest_pins_are_pyprojects_lower_bounds():
    """.ci/matrix tests the site half on the lowest releases pyproject.toml allows: the pins in
    .ci/lowest.txt must be exactly those lower bounds (one place states the bounds)."""
    import re
    import subprocess
    import sys

    from packaging.version import Version

    reqs = subprocess.run(
        [sys.executable, str(ROOT / ".ci" / "site_requirements.py")],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    lower = {}
    for req in reqs:
        name, bound = re.match(r"([A-Za-z0-9_.-]+).*?>=([0-9][^,;\s]*)", req).groups()
        lower[name.lower()] = Version(bound)
    pins = {}
    for line in (ROOT / ".ci" / "lowest.txt").read_text(encoding="utf-8").splitlines():
        if line.strip() and not line.startswith("#"):
            name, version = line.split("==")
            pins[name.strip().lower()] = Version(version)
    assert pins == lower
