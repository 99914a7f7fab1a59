"""Corrections are data: each one applied is reported where it applied, each one that matched
nothing is a warning at its own line, and a broken corrections file is an error at the bad key."""

from __future__ import annotations

from pathlib import Path

import pytest

from roster import RosterError, load_roster

FIXTURES = Path(__file__).parent / "fixtures" / "roster"

ROSTER = (
    "stage3_ag1\t4823122\t4823122\t40823112\t40823112\n"
    "stage3_ag2\t40823113\t40823113\t40823114\t40823114\n"
)


def setup(tmp_path: Path, corrections: str, roster: str = ROSTER) -> tuple[Path, Path]:
    r = tmp_path / "roster.txt"
    r.write_text(roster, encoding="utf-8")
    c = tmp_path / "fix.yml"
    c.write_text(corrections, encoding="utf-8")
    return r, c


SCRIPT_FIXES = """\
typos:
  "4823122": "40823122"
aliases:
  "40823112": "a40823112"
group_names:
  - {replace: "_", with: "-"}
leaders:
  stage3-ag2: "40823114"
"""


def test_each_correction_is_applied_and_reported_with_roster_location(tmp_path: Path) -> None:
    roster, fix = setup(tmp_path, SCRIPT_FIXES)
    r = load_roster(roster, corrections=fix)
    assert r.errors == [] and r.warnings == []
    g1, g2 = r.roster.groups
    assert [(m.id, m.account) for m in g1.members] == [
        ("40823122", "40823122"),
        ("40823112", "a40823112"),
    ]
    assert (g1.name, g2.name, g2.leader) == ("stage3-ag1", "stage3-ag2", "40823114")
    applied = [str(d) for d in r.corrections_applied]
    one, two = f"{roster}:1: info:", f"{roster}:2: info:"
    assert applied == [
        f"{one} member 1 id (col 2): typo: id '4823122' -> '40823122' [{fix}:2]",
        f"{one} member 1 account (col 3): typo: account '4823122' -> '40823122' [{fix}:2]",
        f"{one} member 2 account (col 5): "
        f"alias: account of 40823112 '40823112' -> 'a40823112' [{fix}:4]",
        f"{one} group name (col 1): group name 'stage3_ag1' -> 'stage3-ag1' [{fix}:6]",
        f"{two} group name (col 1): group name 'stage3_ag2' -> 'stage3-ag2' [{fix}:6]",
        f"{two} group name (col 1): leader of stage3-ag2: 40823114 (was 40823113) [{fix}:8]",
    ]
    assert r.to_dict()["groups"][1]["repo_url"] == "https://github.com/40823114/stage3-ag2"


def test_typo_is_exact_not_substring(tmp_path: Path) -> None:
    """The course script replaced substrings on whole lines: '14823122' must not become
    '140823122'."""
    roster, fix = setup(tmp_path, 'typos: {"4823122": "40823122"}\n', "g\t14823122\t14823122\n")
    r = load_roster(roster, corrections=fix)
    assert r.roster.members[0].id == "14823122"
    (w,) = r.warnings
    assert (w.file, w.line, w.field) == (str(fix), 1, "typos.4823122")
    assert "matched nothing" in w.message


def test_unmatched_corrections_warn_at_their_own_lines(tmp_path: Path) -> None:
    text = """\
typos:
  "111": "222"
aliases:
  "333": "x333"
group_names:
  - {regex: "^zzz", with: ""}
leaders:
  nogroup: "40823112"
"""
    roster, fix = setup(tmp_path, text)
    r = load_roster(roster, corrections=fix)
    unmatched = [(d.line, d.field) for d in r.warnings if "matched nothing" in d.message]
    assert unmatched == [
        (2, "typos.111"),
        (4, "aliases.333"),
        (6, "group_names[1]"),
        (8, "leaders.nogroup"),
    ]
    assert r.corrections_applied == []


def test_regex_rules_apply_in_order(tmp_path: Path) -> None:
    text = (
        'group_names:\n  - {regex: "^stage(\\\\d)_", with: "s\\\\1-"}\n'
        '  - {replace: "s3-", with: "S3-"}\n'
    )
    roster, fix = setup(tmp_path, text)
    r = load_roster(roster, corrections=fix)
    assert [g.name for g in r.roster.groups] == ["S3-ag1", "S3-ag2"]
    assert len(r.corrections_applied) == 4


def test_alias_confirming_the_roster_counts_as_matched(tmp_path: Path) -> None:
    roster, fix = setup(
        tmp_path, 'aliases: {"40823112": "a40823112"}\n', "g\t40823112\ta40823112\n"
    )
    r = load_roster(roster, corrections=fix)
    assert r.warnings == []
    (a,) = r.corrections_applied
    assert "already 'a40823112'" in a.message


def test_leader_not_in_group_is_an_error_at_the_corrections_line(tmp_path: Path) -> None:
    roster, fix = setup(tmp_path, 'leaders:\n  stage3_ag1: "40823113"\n')
    r = load_roster(roster, corrections=fix)
    (e,) = r.errors
    assert (e.file, e.line, e.field) == (str(fix), 2, "leaders.stage3_ag1")


def test_bad_corrections_file_errors_name_key_and_line() -> None:
    r = load_roster(FIXTURES / "messy.txt", corrections=FIXTURES / "bad_corrections.yml")
    errs = [
        (d.line, d.field, d.message) for d in r.errors if d.file.endswith("bad_corrections.yml")
    ]
    assert (
        3,
        "aliasses",
        "unknown key 'aliasses' "
        "(expected one of: typos, aliases, group_names, leaders, expected_ids, marks)",
    ) in errs
    assert any(line == 6 and field == "group_names[1]" for line, field, _ in errs)
    assert any(
        line == 7 and field == "leaders" and "expected a mapping" in m for line, field, m in errs
    )
    # nothing from a broken corrections file is half-applied
    assert r.corrections_applied == []
    assert any(d.field == "corrections" and "no corrections applied" in d.message for d in r.errors)


@pytest.mark.parametrize(
    "text, line, field",
    [
        ("typos: [a, b]\n", 1, "typos"),
        ("typos:\n  a: [b]\n", 2, "typos.a"),
        ("group_names:\n  - {replace: a, regex: b, with: c}\n", 2, "group_names[1]"),
        ("group_names:\n  - {regex: '(', with: x}\n", 2, "group_names[1].regex"),
        ("group_names:\n  - {replace: a, with: b, extra: 1}\n", 2, "group_names[1].extra"),
        ("typos:\n  a: b\n  a: c\n", 3, "typos.a"),
        ("- just a list\n", 1, "top level"),
    ],
)
def test_wrong_types_in_corrections_are_errors(
    tmp_path: Path, text: str, line: int, field: str
) -> None:
    roster, fix = setup(tmp_path, text)
    r = load_roster(roster, corrections=fix)
    errs = [(d.line, d.field) for d in r.errors if d.file == str(fix)]
    assert (line, field) in errs, [str(d) for d in r.errors]


def test_corrections_next_to_the_roster_are_found(tmp_path: Path) -> None:
    (tmp_path / "roster.txt").write_text(ROSTER, encoding="utf-8")
    (tmp_path / "roster.corrections.yml").write_text(SCRIPT_FIXES, encoding="utf-8")
    r = load_roster(tmp_path / "roster.txt")
    assert r.corrections_file == str(tmp_path / "roster.corrections.yml")
    assert r.roster.groups[0].name == "stage3-ag1"
    assert any("found next to the roster" in d.message for d in r.infos)
    assert (
        load_roster(tmp_path / "roster.txt", corrections=False).roster.groups[0].name
        == "stage3_ag1"
    )


def test_missing_corrections_file_is_a_roster_error(tmp_path: Path) -> None:
    roster, _ = setup(tmp_path, "")
    with pytest.raises(RosterError, match="no such file"):
        load_roster(roster, corrections=tmp_path / "missing.yml")


def test_empty_corrections_file_is_fine(tmp_path: Path) -> None:
    """An empty file is read (and named) without complaint; the same file, once it holds a rule,
    changes the roster -- so "no complaint" is not "the file was never looked at"."""
    roster, fix = setup(tmp_path, "# nothing yet\n")
    r = load_roster(roster, corrections=fix)
    assert r.corrections_file == str(fix)
    assert [d for d in r.diagnostics if d.file == str(fix)] == []
    assert r.corrections_applied == []
    assert [g.name for g in r.roster.groups] == ["stage3_ag1", "stage3_ag2"]
    fix.write_text('# nothing yet\ngroup_names:\n  - {replace: "_", with: "-"}\n', encoding="utf-8")
    r = load_roster(roster, corrections=fix)
    assert [g.name for g in r.roster.groups] == ["stage3-ag1", "stage3-ag2"]
    assert [(d.line, d.message) for d in r.corrections_applied] == [
        (1, f"group name 'stage3_ag1' -> 'stage3-ag1' [{fix}:3]"),
        (2, f"group name 'stage3_ag2' -> 'stage3-ag2' [{fix}:3]"),
    ]


def test_corrections_can_fix_what_would_be_an_error(tmp_path: Path) -> None:
    """A group name GitHub can't use is fixed by a rule rather than by editing the roster."""
    roster, fix = setup(
        tmp_path,
        'group_names:\n  - {replace: "第一組", with: "group-1"}\n',
        "第一組\t40823101\t40823101\n",
    )
    assert load_roster(roster, corrections=False).errors
    r = load_roster(roster, corrections=fix)
    assert r.errors == [] and r.roster.groups[0].slug == "group-1"


def test_expected_ids_silence_the_shape_warning_for_exactly_those_ids(tmp_path):
    roster = (
        "g1\t40823101\t40823101\t40823102\t40823102\t40623121\t40623121\n"
        "g2\t40823103\t40823103\t40823104\t40823104\t40523252\t40523252\n"
    )
    r, c = setup(
        tmp_path,
        'expected_ids:\n  "40623121": "repeating the course"\n  "40999999": "left"\n',
        roster,
    )
    result = load_roster(r, corrections=c)
    shape = [d for d in result.warnings if "looks unlike" in d.message]
    assert [d.message.split()[1] for d in shape] == ["40523252"]
    assert any(
        "40623121" in d.message and "repeating the course" in d.message
        for d in result.corrections_applied
    )
    unmatched = [d for d in result.warnings if "matched nothing" in d.message]
    assert len(unmatched) == 1 and unmatched[0].line == 3 and "40999999" in unmatched[0].message
