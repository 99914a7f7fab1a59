"""Reading rosters: messy-but-valid input is tolerated and reported, malformed input is an error
that names file, line and field, and no student is ever dropped silently."""

from __future__ import annotations

from pathlib import Path

import pytest

from roster import Diagnostic, RosterError, load_roster

FIXTURES = Path(__file__).parent / "fixtures" / "roster"


def load_text(tmp_path: Path, text: str | bytes, name: str = "r.txt", **kw):
    path = tmp_path / name
    path.write_bytes(text.encode("utf-8") if isinstance(text, str) else text)
    return load_roster(path, corrections=kw.pop("corrections", False), **kw)


def members(result) -> list[tuple[str, str, str]]:
    return [(g.name, m.id, m.account) for g in result.roster.groups for m in g.members]


def find(result, severity: str, text: str) -> list[Diagnostic]:
    return [d for d in result.diagnostics if d.severity == severity and text in d.message]


# --- the messy fixture: everything tolerated at once -------------------------------------


def test_messy_fixture_parses_every_member() -> None:
    r = load_roster(FIXTURES / "messy.txt", corrections=False)
    assert r.errors == []
    assert members(r) == [
        ("team_a", "40823101", "40823101"),
        ("team_a", "40823102", "40823102"),
        ("team_b", "40823103", "a40823103"),
        ("team_b", "40823104", "40823104"),
        ("team_c", "40823105", "40823105"),
        ("team_c", "40823106", "40823106"),
    ]
    notes = {m.id: m.notes for m in r.roster.members}
    assert notes["40823101"] == ("*",)
    assert notes["40823102"] == ("(dropped)",)
    assert notes["40823104"] == ("?",)


def test_messy_fixture_reports_what_it_tolerated() -> None:
    r = load_roster(FIXTURES / "messy.txt", corrections=False)
    infos = [str(d) for d in r.infos]
    file = str(FIXTURES / "messy.txt")
    assert f"{file}:1: info: file: UTF-8 byte-order mark removed" in infos
    assert f"{file}:1: info: file: CRLF line endings normalised (4 lines)" in infos
    assert f"{file}:2: info: line: blank line skipped" in infos
    assert f"{file}:1: info: line: empty member slot(s) 2 skipped" in infos
    assert f"{file}:4: info: line: empty member slot(s) 3-4 skipped" in infos
    assert any("spaces around 2 value(s) trimmed" in d for d in infos)
    warnings = [str(d) for d in r.warnings]
    # three annotations: one warning naming them, each one in full among the info notes
    assert (
        f"{file}:1: warning: member 1 id (col 2): 3 annotations beside ids kept as member "
        "notes: '*' beside 40823101 (line 1), '(dropped)' beside 40823102 (line 1), "
        "'?' beside 40823104 (line 3)" in warnings
    )
    assert (
        f"{file}:1: info: member 1 id (col 2): "
        "annotation '*' beside 40823101 kept as a member note" in infos
    )
    assert (
        f"{file}:3: warning: member 2 account (col 5): "
        "odd trailing id with no account for 40823104; the account defaults to the id" in warnings
    )


# --- single messy cases -----------------------------------------------------------------


@pytest.mark.parametrize(
    "text",
    [
        "g\t40823101\t40823101\t40823102\t40823102\n",
        "\ufeffg\t40823101\t40823101\t40823102\t40823102\n",
        "g\t40823101\t40823101\t40823102\t40823102\r\n",
        "g\t40823101\t40823101\t40823102\t40823102",  # no final newline
        "\n\ng\t40823101\t40823101\t40823102\t40823102\n\n",
        " g \t 40823101\t40823101 \t40823102 \t 40823102\t\t\n",
        "g\t\t\t40823101\t40823101\t\t\t40823102\t40823102\n",
        "g\t40823101\u3000\t40823101\t\u00a040823102\t40823102\n",  # ideographic / no-break spaces
    ],
)
def test_harmless_variations_give_the_same_roster(tmp_path: Path, text: str) -> None:
    r = load_text(tmp_path, text)
    assert r.errors == [] and r.warnings == []
    assert members(r) == [("g", "40823101", "40823101"), ("g", "40823102", "40823102")]


def test_utf16_from_excel_is_read(tmp_path: Path) -> None:
    r = load_text(tmp_path, "g\t40823101\t40823101\r\n".encode("utf-16"))
    assert members(r) == [("g", "40823101", "40823101")]
    assert find(r, "info", "UTF-16")


def test_old_mac_line_endings(tmp_path: Path) -> None:
    r = load_text(tmp_path, "g\t40823101\t40823101\rh\t40823102\t40823102\r")
    assert [g.line for g in r.roster.groups] == [1, 2]


@pytest.mark.parametrize(
    "cell, note",
    [
        ("40823122*", "*"),
        ("40823122 (dropped)", "(dropped)"),
        ("40823122?", "?"),
        ("*40823122", "*"),
        ("40823122（退選）", "（退選）"),
        ("40823122 [audit]", "[audit]"),
    ],
)
def test_annotation_marks_become_notes(tmp_path: Path, cell: str, note: str) -> None:
    r = load_text(tmp_path, f"g\t{cell}\t40823122\n")
    assert r.errors == []
    (m,) = r.roster.members
    assert (m.id, m.account, m.notes) == ("40823122", "40823122", (note,))
    (w,) = find(r, "warning", "annotation")
    assert (w.line, w.field) == (1, "member 1 id (col 2)")
    assert r.to_dict()["groups"][0]["members"][0]["notes"] == [note]


def test_mark_on_account_is_kept_too(tmp_path: Path) -> None:
    r = load_text(tmp_path, "g\t40823122\t40823122 (check)\n")
    assert r.roster.members[0].notes == ("(check)",)
    assert find(r, "warning", "annotation")[0].field == "member 1 account (col 3)"


def test_groups_of_any_size(tmp_path: Path) -> None:
    lines = [
        f"g{n}\t" + "\t".join(f"4082{n:02d}{i:02d}\t4082{n:02d}{i:02d}" for i in range(n))
        for n in (1, 3, 12)
    ]
    r = load_text(tmp_path, "\n".join(lines) + "\n")
    assert [len(g.members) for g in r.roster.groups] == [1, 3, 12]
    assert r.errors == []


def test_odd_trailing_id_defaults_account(tmp_path: Path) -> None:
    r = load_text(tmp_path, "g\t40823101\t40823101\t40823102\n")
    assert members(r)[-1] == ("g", "40823102", "40823102")
    (w,) = find(r, "warning", "odd trailing id")
    assert (w.line, w.field) == (1, "member 2 account (col 5)")


def test_empty_account_in_the_middle_defaults_account(tmp_path: Path) -> None:
    r = load_text(tmp_path, "g\t40823101\t\t40823102\t40823102\n")
    assert members(r)[0] == ("g", "40823101", "40823101")
    assert find(r, "warning", "empty account for 40823101")


# --- malformed: errors naming file, line, field -----------------------------------------


def test_non_id_in_id_field_is_an_error_with_location(tmp_path: Path) -> None:
    r = load_text(tmp_path, "g\t40823101\t40823101\n\nh\t40823102\t40823102\thello\t40823103\n")
    (e,) = r.errors
    assert (e.file, e.line, e.field) == (str(tmp_path / "r.txt"), 3, "member 2 id (col 4)")
    assert "'hello' is not a student id" in e.message
    assert "40823103" in e.message  # the account on that slot is not silently lost
    assert str(e).startswith(f"{tmp_path / 'r.txt'}:3: error: member 2 id (col 4): ")


@pytest.mark.parametrize(
    "name, char", [("bad<name", "<"), ("a/b", "/"), ('x"y', '"'), ("a\x07b", "\\x07")]
)
def test_group_name_with_forbidden_chars_is_an_error(tmp_path: Path, name: str, char: str) -> None:
    r = load_text(tmp_path, f"{name}\t40823101\t40823101\n")
    (e,) = r.errors
    assert (e.line, e.field) == (1, "group name (col 1)")
    assert f"forbidden character '{char}'" in e.message
    assert r.to_dict()["groups"][0]["repo_url"] is None  # no link from a bad name


def test_undecodable_bytes_are_an_error_on_their_line_and_field(tmp_path: Path) -> None:
    data = b"g\t40823101\t40823101\nh\t40823102\t\xff\xfe\n"
    r = load_text(tmp_path, data)
    (e,) = [d for d in r.errors if "undecodable" in d.message]
    assert (e.line, e.field) == (2, "col 3")
    # the rest of the file is still read
    assert ("g", "40823101", "40823101") in members(r)


def test_big5_file_is_reported_not_crashed(tmp_path: Path) -> None:
    r = load_text(tmp_path, "第一組\t40823101\t40823101\n".encode("big5"))
    assert r.errors and all(d.line == 1 for d in r.errors)


def test_space_separated_line_in_a_tab_file_is_an_error_not_a_group(tmp_path: Path) -> None:
    r = load_text(tmp_path, "f\t40823102\t40823102\ng 40823101 40823101\n")
    (e,) = [d for d in r.errors if "no tab" in d.message]
    assert e.line == 2 and "40823101" in e.message


def test_a_file_written_with_spaces_throughout_is_read(tmp_path: Path) -> None:
    """Issue 30: other years' files use spaces (or full-width spaces) instead of tabs."""
    r = load_text(tmp_path, "g 40823101 40823101\u3000a40823102  a40823102\ngroup 2: 40823103\n")
    assert r.ok, [str(d) for d in r.errors]
    assert members(r) == [
        ("g", "40823101", "40823101"),
        ("g", "a40823102", "a40823102"),
        ("group 2", "40823103", "40823103"),
    ]
    assert any("no tabs in the file" in d.message for d in r.infos)


def test_empty_group_name_keeps_ids_in_the_error(tmp_path: Path) -> None:
    r = load_text(tmp_path, "\t40823101\t40823101\n")
    (e,) = [d for d in r.errors if "group name is empty" in d.message]
    assert "40823101" in e.message


def test_account_without_id_is_an_error(tmp_path: Path) -> None:
    r = load_text(tmp_path, "g\t40823101\t40823101\t\t40823102\n")
    (e,) = r.errors
    assert (e.line, e.field) == (1, "member 2 id (col 4)")
    assert "'40823102'" in e.message


def test_empty_file_is_an_error(tmp_path: Path) -> None:
    r = load_text(tmp_path, "")
    assert [d.message for d in r.errors] == ["no groups found in the roster"]


# --- file-level failures raise RosterError only -----------------------------------------


def test_unsupported_extension_is_a_clear_roster_error(tmp_path: Path) -> None:
    path = tmp_path / "roster.xlsx"
    path.write_bytes(b"PK")
    with pytest.raises(
        RosterError, match=r"unsupported roster file type '\.xlsx'; use one of \.csv"
    ):
        load_roster(path)


def test_missing_file_is_a_roster_error(tmp_path: Path) -> None:
    with pytest.raises(RosterError) as info:
        load_roster(tmp_path / "nope.txt")
    assert str(info.value) == f"{tmp_path / 'nope.txt'}: error: file: no such file"


def test_directory_is_a_roster_error(tmp_path: Path) -> None:
    (tmp_path / "d.txt").mkdir()
    with pytest.raises(RosterError, match="is a directory"):
        load_roster(tmp_path / "d.txt")


# --- CSV and YAML inputs -----------------------------------------------------------------


def test_csv_input_groups_rows_in_first_appearance_order() -> None:
    r = load_roster(FIXTURES / "small.csv", corrections=False)
    assert r.format == "csv"
    assert members(r) == [
        ("team-a", "40823101", "40823101"),
        ("team-a", "40823102", "a40823102"),
        ("team-a", "40823105", "40823105"),
        ("team-b", "40823103", "40823103"),
        ("team-b", "40823104", "40823104"),
    ]
    assert r.roster.members[2].line == 6
    assert r.roster.members[2].field == "id (col 2)"
    assert r.errors == []


def test_csv_errors_name_column(tmp_path: Path) -> None:
    r = load_text(tmp_path, "group,id,account\ng,40823101,40823101\ng,x!y,40823102\n", "r.csv")
    (e,) = r.errors
    assert (e.line, e.field) == (3, "id (col 2)")
    assert "40823102" in e.message


def test_csv_without_header_is_an_error(tmp_path: Path) -> None:
    r = load_text(tmp_path, "g,40823101,40823101\ng,40823102,40823102\n", "r.csv")
    e, rows = r.errors
    assert e.field == "header" and "group,id,account" in e.message and "40823101" in e.message
    assert rows.message == "file not read: 2 row(s) including this one"


def test_csv_leader_column_and_unknown_column(tmp_path: Path) -> None:
    text = "group,id,account,leader,name\ng,40823101,40823101,,Ann\ng,40823102,40823102,yes,Bob\n"
    r = load_text(tmp_path, text, "r.csv")
    assert r.roster.groups[0].leader == "40823102"
    (note,) = find(r, "info", "columns not part of the roster, ignored: 'name' (col 5)")
    assert note.line == 1 and not r.warnings


def test_csv_extra_cells_are_not_dropped_silently(tmp_path: Path) -> None:
    r = load_text(tmp_path, "group,id,account\ng,40823101,40823101,40823102\n", "r.csv")
    (e,) = r.errors
    assert "40823102" in e.message and e.field == "col 4"


def test_yaml_input_with_leader_and_notes() -> None:
    r = load_roster(FIXTURES / "small.yml", corrections=False)
    assert r.format == "yaml"
    assert members(r) == [
        ("team-a", "40823101", "40823101"),
        ("team-a", "40823102", "a40823102"),
        ("team-b", "40823103", "40823103"),
        ("team-b", "40823104", "40823104"),
    ]
    assert r.roster.groups[0].leader == "40823102"
    assert r.roster.members[1].notes == ("late join",)
    assert r.roster.members[2].line == 10
    assert r.to_dict()["groups"][0]["repo_url"] == "https://github.com/a40823102/team-a"


def test_yaml_keeps_leading_zeros(tmp_path: Path) -> None:
    r = load_text(
        tmp_path, "groups:\n- name: g\n  members:\n  - {id: 0123, account: x0123}\n", "r.yaml"
    )
    assert r.roster.members[0].id == "0123"


@pytest.mark.parametrize(
    "text, line, field, message",
    [
        (
            "groups:\n- name: g\n  members:\n  - {id: 1, acount: x}\n",
            4,
            "member 1",
            "unknown key 'acount'",
        ),
        ("groups:\n- name: g\n  members: 5\n", 3, "members", "expected a list"),
        ("groups:\n- name: g\n  members:\n  - 40823101\n", 4, "member 1", "must be a mapping"),
        ("grups: []\n", 1, "grups", "unknown key 'grups'"),
        ("groups: [\n", 2, "char 1", "YAML syntax error"),
        (
            "groups:\n- name: g\n  name: h\n  members: [{id: '1'}]\n",
            3,
            "group 1.name",
            "duplicate key",
        ),
    ],
)
def test_yaml_errors_name_line_and_field(
    tmp_path: Path, text: str, line: int, field: str, message: str
) -> None:
    r = load_text(tmp_path, text, "r.yml")
    matching = [d for d in r.errors if message in d.message]
    assert matching, [str(d) for d in r.diagnostics]
    assert (matching[0].line, matching[0].field) == (line, field)


def test_yaml_alias_bomb_is_refused(tmp_path: Path) -> None:
    text = "a: &a [{id: '1'}]\ngroups:\n- {name: g, members: *a}\n- {name: h, members: *a}\n"
    r = load_text(tmp_path, text, "r.yml")
    assert any("aliases are not supported" in d.message for d in r.errors)
