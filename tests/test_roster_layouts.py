"""The teacher's real roster patterns (issue 13): marks beside members, the ids-only layout
of earlier stages, near-duplicate ids; and the roster parts of issue 15 (a catastrophic
group-name regex, terminal escapes in `roster check`)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from roster import diff, load_roster
from roster.cli import main
from roster.emit import to_html, to_json

FIXTURES = Path(__file__).parent / "fixtures" / "roster"
ROOT = Path(__file__).resolve().parents[1]


def write(tmp_path: Path, text: str, name: str = "r.txt", corrections: str | None = None) -> Path:
    path = tmp_path / name
    path.write_bytes(text.encode("utf-8"))
    if corrections is not None:
        (tmp_path / (path.stem + ".corrections.yml")).write_text(corrections, encoding="utf-8")
    return path


def member(result, sid: str):
    return next(m for m in result.roster.members if m.id == sid)


def messages(diags) -> str:
    return "\n".join(str(d) for d in diags)


# --- marks ---------------------------------------------------------------------------------


def test_marks_in_id_and_account_fields_are_kept_on_the_member() -> None:
    r = load_roster(FIXTURES / "marked.txt")
    assert r.ok, messages(r.errors)
    assert member(r, "40823151").marks == ("X",)  # `X 40823151` in an id field
    assert member(r, "40623121").marks == ("X",)  # `40623121 X` in an account field
    assert member(r, "40623121").account == "40623121"
    assert member(r, "40823152").marks == ()
    infos = messages(r.infos)
    assert "marked.txt:2: info: member 2 id (col 4): mark 'X' beside 40823151" in infos
    assert "marked.txt:2: info: member 3 account (col 7): mark 'X' beside 40623121" in infos


def test_marks_are_in_json_and_their_meaning_applies_to_links_and_page() -> None:
    r = load_roster(FIXTURES / "marked.txt")
    data = json.loads(to_json(r))
    members = {m["id"]: m for g in data["groups"] for m in g["members"]}
    assert members["40823151"]["marks"] == ["X"]
    # the corrections say X means "left the group", not linked, struck through
    assert members["40823151"]["repo_url"] is None and members["40823151"]["site_url"] is None
    assert members["40823152"]["repo_url"] == "https://github.com/40823152/cd2021"
    assert "marks" not in members["40823152"]
    page = to_html(r)
    assert '<s><span class="roster-id">40823151</span></s>' in page
    assert '<span class="roster-mark" title="left the group">X</span>' in page
    assert "40823151 repo" not in page and "not linked (left the group)" in page


def test_a_mark_without_a_meaning_is_shown_and_keeps_the_links(tmp_path: Path) -> None:
    r = load_roster(write(tmp_path, "g\t40823101\t40823101\tX 40823102\t40823102\n"))
    assert r.ok and member(r, "40823102").marks == ("X",)
    page = to_html(r)
    assert '<span class="roster-mark">X</span>' in page and "40823102 repo" in page


def test_mark_words_are_configurable_and_anything_else_stays_an_error(tmp_path: Path) -> None:
    text = "g\t40823101\t40823101\tY 40823102\t40823102\tX 40823103\t40823103\n"
    default = load_roster(write(tmp_path, text))
    (err,) = default.errors
    assert (err.line, err.field) == (1, "member 2 id (col 4)")
    assert "'Y 40823102' is not a student id" in err.message
    both = load_roster(write(tmp_path, text), marks=["X", "Y"])
    assert both.ok and member(both, "40823102").marks == ("Y",)
    by_file = load_roster(
        write(tmp_path, text, corrections="marks:\n  Y: dropped\n  X: {links: false}\n")
    )
    assert by_file.ok and by_file.mark_rules["Y"].meaning == "dropped"
    assert not by_file.linked(member(by_file, "40823103"))


def test_a_mark_never_eats_part_of_a_value(tmp_path: Path) -> None:
    r = load_roster(write(tmp_path, "g\t40823101\tXavier\t40823102\tX40823102\n"))
    assert member(r, "40823101").account == "Xavier" and member(r, "40823101").marks == ()
    assert member(r, "40823102").account == "X40823102"


def test_marked_member_listed_again_in_a_new_group_is_a_warning(tmp_path: Path) -> None:
    r = load_roster(FIXTURES / "marked.txt")
    (w,) = [d for d in r.warnings if "two groups" in d.message]
    assert w.line == 3 and "marked X on line 1" in w.message
    plain = load_roster(write(tmp_path, "a\t40823101\t40823101\nb\t40823101\t40823101\n"))
    assert any("two groups" in d.message for d in plain.errors)


def test_roster_diff_reports_marks(tmp_path: Path) -> None:
    old = load_roster(write(tmp_path, "g\t40823101\t40823101\t40823102\t40823102\n", "a.txt"))
    new = load_roster(write(tmp_path, "g\t40823101\t40823101\tX 40823102\t40823102\n", "b.txt"))
    assert diff(old.to_dict(), new.to_dict()) == ["member marked: 40823102 X (in g)"]
    assert diff(new.to_dict(), old.to_dict()) == ["mark removed: 40823102 (was X)"]
    code = main(["diff", str(tmp_path / "a.txt"), str(tmp_path / "b.txt")])
    assert code == 0


def test_marks_config_errors_name_key_and_line(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        "g\t40823101\t40823101\n",
        corrections="marks:\n  X: {links: maybe}\n  '9': x\n  Y: {colour: red}\n",
    )
    r = load_roster(path)
    got = {(d.line, d.field) for d in r.errors if d.file.endswith(".corrections.yml")}
    assert {(2, "marks.X.links"), (3, "marks.9"), (4, "marks.Y.colour")} <= got


# --- ids-only layout ---------------------------------------------------------------------


def test_ids_only_with_header_and_crlf_reads_every_student() -> None:
    r = load_roster(FIXTURES / "ids_only.txt")
    assert r.ok, messages(r.errors)
    assert r.layout == "ids"
    assert [len(g.members) for g in r.roster.groups] == [5, 4, 5]
    assert [m.id for m in r.roster.groups[0].members] == [f"4082310{i}" for i in range(1, 6)]
    # the account is the id, except where the corrections give an alias
    assert {m.account for m in r.roster.members if m.id != "40823112"} == {
        m.id for m in r.roster.members if m.id != "40823112"
    }
    assert member(r, "40823112").account == "a40823112"
    assert member(r, "40823113").marks == ("X",)
    infos = messages(r.infos)
    assert "ids_only.txt:1: info: line: header row skipped: '組別', '組員1'" in infos
    assert "ids layout (detected from the header row (line 1))" in infos
    assert r.warnings == []


@pytest.mark.parametrize(
    "header", ["組別\t組員1\t組員2\t組員3", "group\tmember1\tmember2\tmember3", "\t組員1\t組員2"]
)
def test_header_rows_are_recognised(tmp_path: Path, header: str) -> None:
    r = load_roster(write(tmp_path, header + "\nag1\t40823101\t40823102\t40823103\n"))
    assert r.ok and r.layout == "ids"
    assert [m.id for m in r.roster.members] == ["40823101", "40823102", "40823103"]
    assert any("header row skipped" in d.message and d.line == 1 for d in r.infos)


def test_ids_only_without_header_is_detected_not_halved() -> None:
    r = load_roster(FIXTURES / "ids_only_noheader.txt")
    assert r.ok and r.layout == "ids"
    assert len(r.roster.members) == 11  # read as paired, 6 students would have vanished
    assert "5 of 5 would-be accounts are other students' ids" in messages(r.infos)


def test_declared_paired_file_of_ids_is_an_error(tmp_path: Path) -> None:
    r = load_roster(FIXTURES / "ids_only_noheader.txt", layout="paired")
    (err,) = [d for d in r.errors if d.field == "layout"]
    assert err.line == 1
    assert "5 of 5 accounts are other students' ids" in err.message
    assert "40823102 in the account column after 40823101" in err.message
    header = write(
        tmp_path, "組別\t學號1\t帳號1\t學號2\t帳號2\nag\t40823101\t40823102\t40823103\t40823104\n"
    )
    assert any(d.field == "layout" for d in load_roster(header).errors)


def test_layout_option_for_cli_and_sitegen_yml(tmp_path: Path, capsys) -> None:
    path = write(tmp_path, "ag1\t40823101\t40823101\n")
    assert load_roster(path, layout="ids").roster.groups[0].members[1].id == "40823101"
    assert main(["check", "--layout", "ids", str(FIXTURES / "ids_only_noheader.txt")]) == 0
    assert "(tsv, ids layout): 3 groups, 11 members" in capsys.readouterr().out
    assert main(["check", "--layout", "paired", str(FIXTURES / "ids_only_noheader.txt")]) == 1
    assert "set layout: ids" in capsys.readouterr().out
    assert main(["check", "--layout", "columns", str(path)]) == 2

    from sitegen.config import parse_config
    from sitegen.errors import BuildError

    cfg = parse_config("rosters:\n  - {name: s1, file: s1.txt, layout: ids}\n", tmp_path)
    assert cfg.rosters[0].layout == "ids"
    with pytest.raises(BuildError) as exc:
        parse_config("rosters:\n  - {name: s1, file: s1.txt, layout: pairs}\n", tmp_path)
    assert "rosters[0].layout" in str(exc.value.diagnostics[0])


def test_paired_roster_with_real_accounts_stays_paired(tmp_path: Path) -> None:
    r = load_roster(write(tmp_path, "g\t40823101\tann-lee\t40823102\t40823102\n"))
    assert r.layout == "paired" and member(r, "40823101").account == "ann-lee"


# --- near-duplicate ids ------------------------------------------------------------------


def test_near_duplicate_ids_are_warned_with_both_lines() -> None:
    r = load_roster(FIXTURES / "near_duplicates.txt")
    assert r.ok
    # one warning for the kind, naming both, at the first one's line ...
    (summary,) = [d for d in r.warnings if "one typo away" in d.message]
    assert summary.line == 2 and summary.message.startswith("2 ids are one typo away")
    assert "40832244 ~ 40823244 (lines 2, 3)" in summary.message
    assert "40832242 ~ 40823242 (line 3, outside 40823241-40823250)" in summary.message
    # ... and each one in full, with its line, among the info notes (`check -v`)
    pair = [d for d in r.infos if "one transposition away from 40823244" in d.message]
    assert len(pair) == 1 and pair[0].line == 2
    assert "(line 3, member 1 id (col 2))" in pair[0].message
    (ranged,) = [d for d in r.infos if "outside the class's id range" in d.message]
    assert ranged.line == 3 and "40832242" in ranged.message and "40823242" in ranged.message
    assert "40823241-40823250" in ranged.message


def test_near_duplicates_one_digit_and_expected_ids(tmp_path: Path) -> None:
    text = "a\t40823101\t40823101\t40823102\t40823102\nb\t40923101\t40923101\n"
    r = load_roster(write(tmp_path, text))
    (w,) = [d for d in r.warnings if "away from" in d.message]
    assert "id 40923101 is one digit away from 40823101 (line 1" in w.message
    quiet = load_roster(
        write(tmp_path, text, corrections='expected_ids: {"40923101": other department}\n')
    )
    assert not [d for d in quiet.warnings if "away from" in d.message]


def test_classmates_one_serial_digit_apart_are_not_warned(tmp_path: Path) -> None:
    text = "a\t40823112\t40823112\t40823121\t40823121\t40823122\t40823122\n"
    assert load_roster(write(tmp_path, text)).warnings == []


# --- issue 15: regex time and terminal escapes --------------------------------------------


def test_catastrophic_group_name_regex_does_not_hang(tmp_path: Path) -> None:
    """`(a|aa)+b` backtracks exponentially on a long name: the substitution is bounded in
    time and reported (stdlib `re` ran for hours). Run in a child so a hang fails the test."""
    path = write(
        tmp_path,
        "a" * 60 + "\t40823101\t40823101\n",
        corrections=(
            'group_names:\n  - {regex: "(a|aa)+b", with: "x"}\n  - {regex: "(x+x+)+y", with: "z"}\n'
        ),
    )
    code = (
        "import sys; from roster import load_roster; r = load_roster(sys.argv[1]);"
        "print('\\n'.join(str(d) for d in r.errors))"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, str(path)],
        capture_output=True,
        text=True,
        timeout=60,
        cwd=ROOT,
    )
    assert done.returncode == 0, done.stderr
    assert (
        "r.corrections.yml:2: error: group_names[1]: regex '(a|aa)+b' took over 1 s" in done.stdout
    )
    assert "group_names[2]" not in done.stdout  # (x+x+)+y: the regex engine copes at once


def test_roster_check_never_prints_terminal_escapes(tmp_path: Path, capsys) -> None:
    path = write(
        tmp_path,
        "g\x1b[2J\x1b]0;pwned\x07\t40823101\t40823101\nh\t40823102\tann\x1b[31m\t\x1b[1mX\n",
    )
    assert main(["check", "-v", str(path)]) == 1
    out, err = capsys.readouterr()
    assert "\x1b" not in out + err and "\x07" not in out + err
    assert "g\\x1b[2J" in out


# --- in a built site -----------------------------------------------------------------------


def test_site_roster_pages_show_marks_and_read_the_ids_layout(tmp_path: Path) -> None:
    from sitegen_helpers import run_build, write_tree

    from sitegen.check import check_site

    project = write_tree(
        tmp_path / "p",
        {
            "sitegen.yml": (
                "title: T\nrosters:\n"
                "  - {name: s3, file: data/marked.txt, corrections: data/marked.corrections.yml}\n"
                "  - {name: s1, file: data/s1.txt, layout: ids}\n"
            ),
            "data/marked.txt": (FIXTURES / "marked.txt").read_bytes(),
            "data/marked.corrections.yml": (FIXTURES / "marked.corrections.yml").read_bytes(),
            "data/s1.txt": "ag1\t40823101\t40823102\nag2\t40823103\t40823104\t40823105\n",
            "content/index.md": "# Home\n",
        },
    )
    out = tmp_path / "o"
    run_build(project, out, strict=False)
    page = (out / "s3.html").read_text(encoding="utf-8")
    assert '<s><span class="roster-id">40823151</span></s>' in page
    assert "https://github.com/40823151/cd2021" not in page
    data = json.loads((out / "roster" / "s3.json").read_text(encoding="utf-8"))
    assert [m.get("marks") for m in data["groups"][1]["members"]][:3] == [None, ["X"], ["X"]]
    ids = json.loads((out / "roster" / "s1.json").read_text(encoding="utf-8"))
    assert [len(g["members"]) for g in ids["groups"]] == [2, 3]
    assert check_site(out) == []
    # clearing a mark is reported on the next build
    path = project / "data" / "marked.txt"
    path.write_text(path.read_text(encoding="utf-8").replace("X 40823151", "40823151"), "utf-8")
    report = run_build(project, out)
    assert "roster s3: mark removed: 40823151 (was X)" in report.notes


def test_single_id_per_line_is_the_ids_layout_without_warnings(tmp_path: Path) -> None:
    r = load_roster(write(tmp_path, "ag1\t40823101\r\nag2\t40823102\r\n"))
    assert r.ok and r.layout == "ids" and r.warnings == []
    assert [m.account for m in r.roster.members] == ["40823101", "40823102"]


def test_an_account_field_holding_only_a_mark_defaults_the_account(tmp_path: Path) -> None:
    r = load_roster(write(tmp_path, "g\t40823101\t40823101\t40823102\tX\n"))
    assert r.ok and r.warnings == []
    assert (member(r, "40823102").account, member(r, "40823102").marks) == ("40823102", ("X",))
