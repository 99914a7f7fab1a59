"""The shared located form: one Diagnostic, one line format, one line-numbered YAML walker.

A roster problem, a sitegen.yml problem and an unreadable scene are all reported the same way
(``file:line: severity: field: message``), so a teacher learns the form once."""

from __future__ import annotations

import pytest

from located.diagnostics import WHOLE_FILE, Diagnostic, LocatedError
from located.yaml import compose
from located.yamlwalk import ROOT, Walker


def test_one_line_format_with_line_column_and_whole_file():
    assert Diagnostic("a.yml", 3, "title", "must be a string").format() == (
        "a.yml:3: error: title: must be a string"
    )
    assert str(Diagnostic("a.yml", 3, "", "YAML syntax error", column=7)) == (
        "a.yml:3:7: error: YAML syntax error"
    )
    whole = Diagnostic("r.txt", WHOLE_FILE, "file", "no such file", "warning")
    assert whole.format() == "r.txt: warning: file: no such file"
    # quoted input cannot break the line or reach the terminal raw
    bad = Diagnostic("x\n.txt", 1, "col\t2", "name 'a\x1b[2Jb'")
    assert "\n" not in bad.format() and "\x1b" not in bad.format()
    assert bad.format() == "x\\n.txt:1: error: col\\t2: name 'a\\x1b[2Jb'"


def test_the_three_packages_share_the_type():
    from roster import Diagnostic as RosterDiagnostic
    from roster import RosterError
    from sims.scene.errors import SceneError
    from sitegen.errors import Diagnostic as SiteDiagnostic

    assert RosterDiagnostic is SiteDiagnostic is Diagnostic
    for error in (
        RosterError("r.txt", None, "file", "no such file"),
        SceneError("s.ttt", "header", "bad"),
    ):
        assert isinstance(error, LocatedError)
        assert str(error) == error.diagnostic.format()
    assert (
        str(SceneError("s.xml", "hinge", "bad range", line=4)) == "s.xml:4: error: hinge: bad range"
    )


def _walk(text: str, **kw) -> tuple[Walker, object]:
    walker = Walker("f.yml", **kw)
    return walker, compose(text, "f.yml")


def test_walker_reports_each_problem_at_its_line():
    w, root = _walk("title: x\nsims:\n  fps: fast\ntitle: y\nbogus: 1\n")
    keys = w.keys(root, ROOT, {"title", "sims"})
    assert set(keys) == {"title", "sims"}
    sims = w.keys(keys["sims"], "sims", {"fps"})
    assert w.value(sims["fps"], "sims.fps", "int") is None
    assert [d.format() for d in w.problems] == [
        "f.yml:4: error: title: duplicate key 'title' (first at line 1)",
        "f.yml:5: error: bogus: unknown key 'bogus' (expected one of: sims, title)",
        "f.yml:3: error: sims.fps: must be a whole number, got 'fast'",
    ]


def test_walker_keeps_exact_text_and_can_refuse_aliases():
    w, root = _walk("id: 0123\nlist: &a [1]\nagain: *a\n", aliases=False)
    items = {k: v for k, _, v in w.mapping(root, ROOT)}
    assert w.text(items["id"], "id") == "0123"  # not the int 83
    assert w.sequence(items["list"], "list") != []
    assert w.sequence(items["again"], "again") == []
    # the alias is the anchored node itself: it is reported where the anchor defines it
    assert [(d.line, d.message) for d in w.problems] == [
        (2, "YAML anchors/aliases are not supported here")
    ]


@pytest.mark.parametrize(
    "kind,value", [("str", "1"), ("int", "1.5"), ("num", "true"), ("bool", "1")]
)
def test_walker_type_checks(kind, value):
    w, root = _walk(f"v: {value}\n")
    assert w.value(root.value[0][1], "v", kind) is None
    assert w.problems[0].line == 1 and w.problems[0].field == "v"


def test_a_yaml_error_is_a_located_error_with_file_line_and_column():
    """A caller that reports located problems one way (``except LocatedError``) also catches
    every YAML failure: syntax errors and broken limits, each at its line."""
    with pytest.raises(LocatedError) as info:
        compose("title: ok\nlist: [1,\n", "site.yml")
    assert (info.value.file, info.value.line) == ("site.yml", 3)
    assert info.value.diagnostic.column == 1
    assert str(info.value) == "site.yml:3:1: error: " + info.value.message
    assert info.value.message.startswith("YAML syntax error")
    with pytest.raises(LocatedError) as info:
        compose("a: &a [x]\nb: [*a, *a]\n", "f.yml", max_aliases=1)
    assert (info.value.line, info.value.field) == (2, "")
    assert "more than 1 YAML aliases" in str(info.value)


def test_sitegen_config_reports_a_yaml_syntax_error_at_its_line(tmp_path):
    from sitegen.config import parse_config
    from sitegen.errors import BuildError

    with pytest.raises(BuildError) as info:
        parse_config("title: x\nclips: [\n", tmp_path)
    assert [d.format() for d in info.value.diagnostics] == [
        "sitegen.yml:3:1: error: YAML syntax error: did not find expected node content"
    ]
