"""Every roster layout the course has used since 2019 (issue 30), read as the course meant it.

The two shared rosters are compared with what the course's own parsers compute from them,
written down here as data (the parsers are named in ../shared/data/rosters/SOURCES.md):

- `cd2022_w4_2a_group.txt` (`w4_2a_get_grp1_num_of_members.txt`, `2a_w3_grouping_brython.py`
  in 40923134/cd2022_guide): skip the header, split each line into id, GitHub account and
  group number, the id where the account is empty; groups by number, members in file order.
- `mdecycu_cd2024_2a_grouping.txt` (`gen_grp_html.py` in mdecycu/cd2024): a line naming the
  class (`2ag6`) is a group title, the lines after it its ids; titles sorted.

The other tests build the whole class of inputs from text written here: tabs or spaces,
BOM, CRLF, blank lines, header variants, full-width characters, for each layout.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from roster import load_roster
from roster.cli import main
from roster.labels import natural_key
from tests.shared_data import shared

# --- what the course's parsers compute from the shared files -------------------------------

CD2022 = {  # group number -> (id, account) in file order
    "1": [
        ("40923101", "a40923101"),
        ("40923103", "40923103"),
        ("40923108", "40923108"),
        ("40923119", "40923119"),
        ("40923137", "s40923137"),
        ("40923154", "40923154"),
        ("40923156", "ZHILIN-0817"),
        ("40971134", "40971134"),
    ],
    "2": [
        ("40923102", "40923102"),
        ("40923104", "409231044"),
        ("40923105", "40923105"),
        ("40923106", "40923106"),
        ("40923107", "40923107"),
        ("40923110", "40923110"),
        ("40923121", "40923121"),
        ("40923153", "40923153"),
    ],
    "3": [
        ("40923109", "CYC40923109"),
        ("40923111", "40923111"),
        ("40923114", "40923114"),
        ("40923115", "jason60714"),
        ("40923122", "40923122"),
        ("40923129", "40923129"),
        ("40923146", "a40923146"),
        ("40923148", "40923148"),
    ],
    "4": [
        ("40923116", "40923116"),
        ("40923124", "40923124"),
        ("40923125", "40923125"),
        ("40923126", "40923126-1"),
        ("40923127", "40923127-1"),
        ("40923128", "40923128"),
        ("40923138", "40923138"),
        ("40923143", "40923143"),
    ],
    "5": [
        ("40923123", "40923123"),
        ("40923131", "40923131"),
        ("40923133", "40923133"),
        ("40923134", "40923134"),
        ("40923135", "40923135"),
        ("40923139", "40923139"),
        ("40923142", "40923142"),
        ("40923151", "40923151"),
    ],
    "6": [
        ("40923113", "40923113"),
        ("40923130", "40923130"),
        ("40923140", "40923140"),
        ("40923144", "40923144"),
        ("40923145", "40923145"),
        ("40923149", "40923149r"),
        ("40923150", "40923150"),
        ("40923152", "40923152"),
    ],
    "7": [
        ("40823132", "40823132"),
        ("40823143", "40823143"),
        ("40923117", "Maxlee999"),
        ("40923118", "40923118"),
        ("40923120", "40923120"),
        ("40923136", "40923136-1"),
        ("40923147", "40923147"),
        ("40923157", "40923157"),
    ],
}
CD2024 = {  # group title -> ids in file order (accounts are the ids)
    "2ag1": ["40923108", "40923101", "40923103", "40923113", "40923156"],
    "2ag2": ["40923105", "40923107", "40923102", "40923104", "40923106", "40923110"],
    "2ag3": ["40923148", "40923109", "40923154", "40923119", "40971134"],
    "2ag4": ["40923129", "40923111", "40923114", "40923115", "40923116", "40923122", "40923146"],
    "2ag5": ["40923123", "40923137", "40923142", "40923151"],
    "2ag6": ["40923118", "40923120", "40923125", "40923128", "40923124", "40923126"],
    "2ag7": ["40923131", "40923133", "40923134", "40923135", "40923136", "40923145"],
}


def groups_of(result) -> dict[str, list[tuple[str, str]]]:
    return {g.name: [(m.id, m.account) for m in g.members] for g in result.roster.groups}


def test_cd2022_one_member_a_line_gives_the_course_groups() -> None:
    result = load_roster(shared("data", "rosters", "cd2022_w4_2a_group.txt"), corrections=False)
    assert result.errors == [] and result.layout == "rows"
    assert groups_of(result) == {f"group {n}": members for n, members in CD2022.items()}
    # one warning per kind of anomaly, not one per line (there were 109)
    assert len(result.warnings) <= 5
    kinds = " | ".join(d.message for d in result.warnings)
    assert "2 ids look unlike the others" in kinds and "40823132 (line 2)" in kinds
    assert "409231044" in kinds  # an account that is the id with a digit glued on
    assert not [d for d in result.warnings if "s40923137" in d.message]  # the id with a letter
    assert any("header row skipped" in d.message and d.line == 1 for d in result.infos)


def test_cd2024_label_then_ids_gives_the_course_groups() -> None:
    result = load_roster(shared("data", "rosters", "mdecycu_cd2024_2a_grouping.txt"))
    assert result.errors == [] and result.warnings == [] and result.layout == "blocks"
    assert groups_of(result) == {name: [(i, i) for i in ids] for name, ids in CD2024.items()}
    assert list(groups_of(result)) == sorted(CD2024)  # titles sorted, as gen_grp_html did


@pytest.mark.parametrize("name", ["cd2022_w4_2a_group.txt", "mdecycu_cd2024_2a_grouping.txt"])
def test_links_for_every_member(name: str, capsys) -> None:
    path = shared("data", "rosters", name)
    assert main(["links", str(path), "--format", "json", "--course-repo", "cd2022"]) == 0
    data = json.loads(capsys.readouterr().out)
    members = [m for g in data["groups"] for m in g["members"]]
    assert len(members) == (56 if name.startswith("cd2022") else 39)
    for m in members:
        assert m["repo_url"] == f"https://github.com/{m['account']}/cd2022"
        assert m["site_url"] == f"https://{m['account']}.github.io/cd2022"
    assert all(g["repo_url"] and g["site_url"] for g in data["groups"])


# --- one member a line, with a group column (2022) -------------------------------------------


def load(tmp_path: Path, text: str | bytes, name: str = "r.txt", **kw):
    path = tmp_path / name
    path.write_bytes(text.encode("utf-8") if isinstance(text, str) else text)
    return load_roster(path, corrections=kw.pop("corrections", False), **kw)


ROWS = [("40923101", "a40923101", "1"), ("40923102", "40923102", "2")]
ROWS += [("40923103", "40923103", "1"), ("40923104", "jason60714", "2")]
ROWS_EXPECTED = {
    "group 1": [("40923101", "a40923101"), ("40923103", "40923103")],
    "group 2": [("40923102", "40923102"), ("40923104", "jason60714")],
}


@pytest.mark.parametrize(
    "header",
    ["2a\tgithub 帳號\t組別", "學號\tGitHub帳號\t組別", "student id\taccount\tgroup", None],
)
@pytest.mark.parametrize("sep", ["\t", " ", "  ", "\u3000", ","])
@pytest.mark.parametrize("eol", ["\n", "\r\n"])
def test_rows_variants(tmp_path: Path, header: str | None, sep: str, eol: str) -> None:
    lines = [sep.join(r) for r in ROWS]
    if header is not None:
        lines.insert(0, header if sep == "\t" else header.replace("\t", sep))
    lines.insert(2, "")  # a blank line
    r = load(tmp_path, "\ufeff" + eol.join(lines) + eol)
    assert r.errors == [], [str(d) for d in r.errors]
    assert r.layout == "rows" and groups_of(r) == ROWS_EXPECTED


def test_rows_group_first_full_width_and_extra_column(tmp_path: Path) -> None:
    text = (
        "組別\t學號\t姓名\tGitHub帳號\n"
        "２\t４０９２３１０２\t王小明\t40923102\n"
        "1\t40923101\t李小華\ta40923101\n"
        "2\t40923104\t陳大文\tjason60714\n"
        "1\t40923103\t林一\t\n"
    )
    r = load(tmp_path, text)
    assert r.errors == [] and r.layout == "rows"
    assert groups_of(r) == ROWS_EXPECTED
    infos = " | ".join(d.message for d in r.infos)
    assert "full-width" in infos and "ignored: column 3 (name" in infos
    assert "王小明" not in json.dumps(r.to_dict(), ensure_ascii=False)  # names stay out


def test_rows_student_without_group_is_named_not_dropped(tmp_path: Path) -> None:
    text = "\n".join("\t".join(r) for r in ROWS) + "\n40923105\t40923105\t\n40923106\t\t\n"
    r = load(tmp_path, text)
    assert groups_of(r) == ROWS_EXPECTED
    (w,) = [d for d in r.warnings if "no group yet" in d.message]
    assert w.line == 5 and "40923105 (line 5), 40923106 (line 6)" in w.message


# --- a group label, then ids (2019, 2023-24) --------------------------------------------------

BLOCKS_2019 = """共有 5 位學員
--------------------
group 1:

40623108
40623122
40623129
--------------------
group 2:

40423160
40623142"""


@pytest.mark.parametrize("eol", ["\n", "\r\n"])
@pytest.mark.parametrize("bom", ["", "\ufeff"])
def test_blocks_2019_with_title_and_separators(tmp_path: Path, eol: str, bom: str) -> None:
    r = load(tmp_path, bom + BLOCKS_2019.replace("\n", eol))
    assert r.errors == [] and r.layout == "blocks"
    assert groups_of(r) == {
        "group 1": [("40623108", "40623108"), ("40623122", "40623122"), ("40623129", "40623129")],
        "group 2": [("40423160", "40423160"), ("40623142", "40623142")],
    }
    assert any("title line skipped: '共有 5 位學員'" in d.message for d in r.infos)


def test_blocks_labels_accounts_marks_and_full_width(tmp_path: Path) -> None:
    text = (
        "ｇ１：\n40923101\ta40923101\nX 40923102\n2ag10\n40923110 s40923110\n2ag2\n  40923103*  \n"
    )
    r = load(tmp_path, text)
    assert r.errors == [], [str(d) for d in r.errors]
    assert list(groups_of(r)) == ["2ag2", "2ag10", "g1"]  # natural order
    assert groups_of(r)["g1"] == [("40923101", "a40923101"), ("40923102", "40923102")]
    assert r.roster.groups[2].members[1].marks == ("X",)
    assert groups_of(r)["2ag10"] == [("40923110", "s40923110")]
    assert r.roster.groups[0].members[0].notes == ("*",)


def test_blocks_id_before_any_label_is_an_error(tmp_path: Path) -> None:
    r = load(tmp_path, "2ag1\n40923101\n40923102\n2ag2\n40923103\n")
    assert r.ok
    bad = load(tmp_path, "40923109\n2ag1\n40923101\n40923102\n2ag2\n40923103\n")
    assert [(d.line, d.message) for d in bad.errors] == [
        (1, "student '40923109' is listed before any group label line")
    ]


# --- a Python list of lists (2020) -------------------------------------------------------------


def test_lists_layout(tmp_path: Path) -> None:
    text = "[['40723104', '40723107'], ['40623143', '40723108',\n '40723127']]\n"
    r = load(tmp_path, text)
    assert r.errors == [] and r.layout == "lists"
    assert [(g.name, [m.id for m in g.members]) for g in r.roster.groups] == [
        ("group 1", ["40723104", "40723107"]),
        ("group 2", ["40623143", "40723108", "40723127"]),
    ]
    assert r.roster.groups[1].members[2].line == 2
    bare = load(tmp_path, "[[40723201, 40723206], [40523253]]")
    assert [len(g.members) for g in bare.roster.groups] == [2, 1]
    broken = load(tmp_path, "[['40723104', x!y]]")
    assert [d.field for d in broken.errors] == ["id (col 15)"]


# --- files that are not rosters: one error each -----------------------------------------------


@pytest.mark.parametrize(
    ("text", "said"),
    [
        ("40423111\n40423122\n40423142\n" * 10, "a list of 30 student ids with no group labels"),
        ("1 .  40932134\n2 .  41023105\n3 .  41023109\n", "a numbered list of 3 students"),
        ("This is the week 3 report.\nNothing here.\n", "2 line(s) of text with no student id"),
    ],
)
def test_not_a_roster_is_one_error(tmp_path: Path, text: str, said: str) -> None:
    r = load(tmp_path, text)
    (e,) = r.errors
    assert e.field == "layout" and said in e.message and "expected one of" in e.message
    assert r.roster.groups == ()


def test_account_list_is_refused_as_a_roster_and_used_as_aliases(tmp_path: Path) -> None:
    accounts = tmp_path / "accounts.txt"
    accounts.write_text(
        "學號\tgithub 帳號\n40723101\ts40723101\n40723102\ts40723102\n40823199\tzed\n", "utf-8"
    )
    (e,) = load_roster(accounts).errors
    assert "id -> account list" in e.message and "--aliases" in e.message
    roster = tmp_path / "r.txt"
    roster.write_text("2ag1\n40723101\n40723102\n", "utf-8")
    r = load_roster(roster, aliases=accounts)
    assert r.ok and groups_of(r) == {"2ag1": [("40723101", "s40723101"), ("40723102", "s40723102")]}
    applied = [d.message for d in r.corrections_applied]
    assert f"alias: account of 40723101 '40723101' -> 's40723101' [{accounts}:2]" in applied
    assert any("1 of 3 aliases in the list name no student" in m for m in applied)
    # the corrections' own alias wins over the list's
    (tmp_path / "r.corrections.yml").write_text('aliases: {"40723101": mine}\n', "utf-8")
    fixed = load_roster(roster, aliases=accounts)
    assert groups_of(fixed)["2ag1"][0] == ("40723101", "mine")


@pytest.mark.parametrize(
    ("name", "text"),
    [
        ("a.csv", "學號,姓名,GitHub帳號\n40723101,王,s40723101\n"),
        ("a.yml", 'aliases:\n  "40723101": s40723101\n'),
        ("a.txt", "40723101 s40723101\n40723105 s40723105\n"),
    ],
)
def test_alias_list_formats(tmp_path: Path, name: str, text: str, capsys) -> None:
    (tmp_path / name).write_text(text, "utf-8")
    roster = tmp_path / "r.txt"
    roster.write_text("g1\t40723101\n", "utf-8")
    assert main(["links", str(roster), "--aliases", str(tmp_path / name), "--format", "json"]) == 0
    (member,) = json.loads(capsys.readouterr().out)["groups"][0]["members"]
    assert member["account"] == "s40723101"


def test_csv_export_with_extra_columns(tmp_path: Path) -> None:
    text = (
        "2a 分組名單,,,,\n"
        "學號,姓名,系級,GitHub帳號,組別\n"
        "40923101,王小明,機械二甲,a40923101,1\n"
        "40923102,李小華,機械二甲,40923102,2\n"
        "40923103,林一,機械二甲,,1\n"
    )
    r = load(tmp_path, text, "r.csv")
    assert r.errors == [] and r.warnings == []
    assert groups_of(r) == {
        "group 1": [("40923101", "a40923101"), ("40923103", "40923103")],
        "group 2": [("40923102", "40923102")],
    }
    notes = " | ".join(d.message for d in r.infos)
    assert "ignored: '姓名' (col 2), '系級' (col 3)" in notes and "title row" in notes


def test_many_ids_with_letters_are_one_info_and_cohorts_one_warning(tmp_path: Path) -> None:
    """`s40723140` for 40723140 (the teacher's realA) is the usual account; other cohorts'
    ids are worth one warning naming them, not one each."""
    pairs = [(f"407231{n:02d}", f"s407231{n:02d}") for n in range(1, 9)]
    pairs += [(f"408232{n:02d}", f"408232{n:02d}") for n in range(1, 13)]
    text = "stage3-bg4\t" + "\t".join(f"{i}\t{a}" for i, a in pairs) + "\n"
    r = load(tmp_path, text)
    assert r.errors == []
    (w,) = r.warnings
    assert w.message.startswith("8 ids look unlike the others")
    assert "and 3 more (-v lists them)" in w.message
    (note,) = [d for d in r.infos if d.message.startswith("8 accounts are the student id")]
    assert "s40723101 for 40723101 (line 1)" in note.message


# --- generated: any roster, written in each layout with each year's habits ------------------

CLASS_IDS = st.integers(1, 99).map(lambda n: f"409231{n:02d}")
ACCOUNT = st.one_of(st.none(), st.sampled_from(["a", "s", "CYC"]), st.just("jason"))


@st.composite
def rosters(draw) -> dict[int, list[tuple[str, str]]]:
    """Group number -> members (id, account), ids unique across the roster."""
    ids = draw(st.lists(CLASS_IDS, min_size=4, max_size=24, unique=True))
    n_groups = draw(st.integers(1, max(1, len(ids) // 2)))
    out: dict[int, list[tuple[str, str]]] = {}
    for i, sid in enumerate(ids):
        kind = draw(ACCOUNT)
        account = sid if kind is None else (f"{kind}{sid}" if kind != "jason" else f"j{sid[-4:]}x")
        out.setdefault(i % n_groups + 1, []).append((sid, account))
    return out


def _expected(groups: dict[int, list[tuple[str, str]]], name: str) -> dict:
    return {name.format(n): groups[n] for n in sorted(groups)}


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    groups=rosters(),
    sep=st.sampled_from(["\t", " ", "\u3000", ","]),
    eol=st.sampled_from(["\n", "\r\n"]),
    bom=st.sampled_from(["", "\ufeff"]),
    header=st.booleans(),
    blank=st.booleans(),
    order=st.randoms(use_true_random=False),
)
def test_any_roster_in_rows_and_blocks_reads_back(
    tmp_path: Path, groups, sep, eol, bom, header, blank, order
) -> None:
    rows = [(sid, acc, str(n)) for n, members in groups.items() for sid, acc in members]
    order.shuffle(rows)
    lines = [sep.join(r) for r in rows]
    if header:
        lines.insert(0, sep.join(["學號", "github", "組別"]))
    if blank:
        lines.insert(len(lines) // 2, "")
    if len({n for *_, n in rows}) * 2 <= len(rows):  # a group column must repeat to be seen
        r = load(tmp_path, bom + eol.join(lines) + eol)
        assert r.errors == [] and r.layout == "rows", [str(d) for d in r.errors]
        in_file = [r[:2] for r in rows]  # members keep file order within their group
        assert groups_of(r) == {
            name: sorted(members, key=in_file.index)
            for name, members in _expected(groups, "group {}").items()
        }
    blocks = []
    for n in sorted(groups, reverse=True):
        blocks.append(f"2ag{n}" if n % 2 else f"group {n}:")
        blocks += [sid if sid == acc else f"{sid}{sep}{acc}" for sid, acc in groups[n]]
        if blank:
            blocks.append("-" * 20)
    r = load(tmp_path, bom + eol.join(blocks) + eol)
    assert r.errors == [] and r.layout == "blocks", [str(d) for d in r.errors]
    names = {n: (f"2ag{n}" if n % 2 else f"group {n}") for n in groups}
    by_label = sorted(groups, key=lambda n: natural_key(names[n]))
    assert groups_of(r) == {names[n]: groups[n] for n in by_label}


# --- a GitHub team list (2025) ---------------------------------------------------------------

TEAMS = """Processing team: g1
Login: 41223251, ID: 144990130, URL: https://github.com/41223251
Login: jjjay41223212, ID: 144991701, URL: https://github.com/jjjay41223212
Login: leeshaowei0716, ID: 144992123, URL: https://github.com/leeshaowei0716
Processing team: g10
Login: 41223208-hw, ID: 183057631, URL: https://github.com/41223208-hw
Login: supowen, ID: 91449769, URL: https://github.com/supowen
Processing team: g2
Login: 41223216, ID: 144990706, URL: https://github.com/41223216

All members: ['41223251', 'jjjay41223212', 'leeshaowei0716', '41223208-hw', 'supowen', '41223216']
"""


def test_github_team_list_is_read_and_an_alias_list_names_the_logins(tmp_path: Path) -> None:
    r = load(tmp_path, TEAMS)
    assert r.errors == [] and r.layout == "blocks"
    assert groups_of(r) == {
        "g1": [
            ("41223251", "41223251"),
            ("41223212", "jjjay41223212"),
            ("leeshaowei0716", "leeshaowei0716"),
        ],
        "g2": [("41223216", "41223216")],
        "g10": [("41223208", "41223208-hw"), ("supowen", "supowen")],
    }
    (w,) = r.warnings
    assert w.message.startswith("2 members are known by GitHub login alone")
    assert any("summary line skipped: its 6 names" in d.message for d in r.infos)
    # the class list (id -> account) gives the logins their ids
    accounts = tmp_path / "2b.txt"
    accounts.write_text("學號\tgithub\n41223213\tleeshaowei0716\n41223240\tsupowen\n", "utf-8")
    named = load(tmp_path, TEAMS, aliases=accounts)
    assert named.errors == [] and named.warnings == []
    assert groups_of(named)["g1"][2] == ("41223213", "leeshaowei0716")
    assert groups_of(named)["g10"][1] == ("41223240", "supowen")
    assert any(
        "id of GitHub login 'supowen': 41223240" in d.message for d in named.corrections_applied
    )
    # an "All members" line naming someone not in any group is not skipped
    odd = load(tmp_path, TEAMS.replace("'41223216']", "'41223216', 'newcomer9']"))
    assert any("has no members" in d.message for d in odd.errors)


# --- in a built site: layout and aliases from sitegen.yml -------------------------------------


def test_site_roster_in_blocks_layout_with_an_alias_list(tmp_path: Path) -> None:
    from sitegen_helpers import run_build, write_tree

    from sitegen.check import check_site
    from sitegen.config import parse_config
    from sitegen.errors import BuildError

    project = write_tree(
        tmp_path / "p",
        {
            "sitegen.yml": "title: T\ncourse_repo: cd2024\nrosters:\n"
            "  - {name: g, file: data/2a_grouping.txt, aliases: data/2a.txt, layout: blocks}\n",
            "data/2a_grouping.txt": "2ag2\n40923105\n40923107\n2ag1\n40923108\n",
            "data/2a.txt": "學號\tgithub 帳號\n40923105\tCYC40923105\n40923108\ts40923108\n",
            "content/index.md": "# Home\n\n::: roster g\n",
        },
    )
    out = tmp_path / "o"
    run_build(project, out, strict=True)
    page = (out / "g.html").read_text(encoding="utf-8")
    assert page.index("2ag1") < page.index("2ag2")
    assert 'href="https://github.com/CYC40923105/cd2024"' in page
    assert 'href="https://s40923108.github.io/cd2024"' in page
    assert check_site(out) == []
    (project / "data" / "2a.txt").unlink()
    with pytest.raises(BuildError) as exc:
        run_build(project, out, strict=True)
    said = [str(d) for d in exc.value.diagnostics]
    assert any("data/2a.txt: error: rosters[g].aliases: file not found" in d for d in said)
    with pytest.raises(BuildError) as bad:
        parse_config("rosters:\n  - {name: s1, file: s1.txt, layout: columns}\n", tmp_path)
    assert "auto, paired, ids, rows, blocks, lists" in str(bad.value.diagnostics[0])
