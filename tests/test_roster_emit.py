"""Output: the exact to_dict shape sitegen relies on, deterministic JSON, escaped HTML, CSV that
reads back to the same roster."""

from __future__ import annotations

import json
import re
from pathlib import Path

from roster import load_roster
from roster.emit import to_csv, to_html, to_json

FIXTURES = Path(__file__).parent / "fixtures" / "roster"


def small():
    return load_roster(FIXTURES / "small.yml", corrections=False, course_repo="cd2021")


def test_to_dict_has_exactly_the_documented_shape() -> None:
    data = small().to_dict()
    assert set(data) == {"groups"}
    group = data["groups"][0]
    assert set(group) == {"name", "slug", "leader", "repo_url", "site_url", "members"}
    assert set(group["members"][0]) == {"id", "account", "repo_url", "site_url", "notes"}
    assert group["members"][1] == {
        "id": "40823102",
        "account": "a40823102",
        "repo_url": "https://github.com/a40823102/cd2021",
        "site_url": "https://a40823102.github.io/cd2021",
        "notes": ["late join"],
    }
    assert (group["leader"], group["repo_url"], group["site_url"]) == (
        "40823102",
        "https://github.com/a40823102/team-a",
        "https://a40823102.github.io/team-a",
    )


def test_course_repo_is_a_parameter() -> None:
    r = load_roster(FIXTURES / "small.yml", corrections=False, course_repo="cd2022")
    assert r.to_dict()["groups"][1]["members"][0]["site_url"] == "https://40823103.github.io/cd2022"


def test_json_is_sorted_indented_and_deterministic() -> None:
    text = to_json(small())
    assert text.endswith("}\n")
    assert text == to_json(small())
    assert json.loads(text) == small().to_dict()
    assert text == json.dumps(json.loads(text), sort_keys=True, indent=2, ensure_ascii=False) + "\n"


def test_json_keeps_non_ascii(tmp_path: Path) -> None:
    path = tmp_path / "r.txt"
    path.write_text("g\t40823101 (退選)\t40823101\n", encoding="utf-8")
    assert "(退選)" in to_json(load_roster(path, corrections=False))


def test_html_has_one_section_per_group_with_counts() -> None:
    html = to_html(small())
    assert html.count('<section class="roster-group" id="group-') == 2
    assert 'id="group-team-a"' in html and 'id="group-team-b"' in html
    assert '<p class="roster-summary">2 groups, 4 members</p>' in html
    assert "(2 members)" in html
    assert '<a href="https://github.com/a40823102/team-a">team-a repo</a>' in html
    assert '<a href="https://40823101.github.io/cd2021">40823101 site</a>' in html


def test_html_escapes_everything(tmp_path: Path) -> None:
    """Free text (notes) reaches the page; it is escaped in text, and nothing else is unescaped."""
    path = tmp_path / "r.yml"
    path.write_text(
        "groups:\n- name: g\n  members:\n  - {id: '40823101', account: '40823101', "
        'notes: [\'<script>alert("x")</script>\', "it\'s & co"]}\n',
        encoding="utf-8",
    )
    r = load_roster(path, corrections=False)
    assert r.errors == []
    html = to_html(r)
    assert "<script>" not in html
    assert "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt;" in html
    assert "it&#x27;s &amp; co" in html


def test_unsafe_values_never_become_links(tmp_path: Path) -> None:
    path = tmp_path / "r.txt"
    path.write_text("g<x\t40823101\tjavascript:alert(1)\t40823102\t../x\n", encoding="utf-8")
    r = load_roster(path, corrections=False)
    assert r.errors
    for out in (to_html(r), to_csv(r), to_json(r)):
        hrefs = re.findall(r'href="([^"]*)"', out)
        assert all(
            h.startswith("https://") and ".." not in h and "javascript" not in h for h in hrefs
        )
    assert 'href="javascript' not in to_html(r)
    assert "&lt;" in to_html(r)  # the bad group name is shown escaped, not linked
    assert '<span class="roster-nolink">40823101 repo</span>' in to_html(r)


def test_csv_has_links_and_reads_back_to_the_same_roster(tmp_path: Path) -> None:
    r = small()
    text = to_csv(r)
    header, first = text.splitlines()[:2]
    assert header == "group,id,account,leader,notes,repo_url,site_url,group_repo_url,group_site_url"
    assert first.startswith("team-a,40823101,40823101,,,https://github.com/40823101/cd2021,")
    path = tmp_path / "back.csv"
    path.write_text(text, encoding="utf-8")
    again = load_roster(path, corrections=False)
    assert again.errors == []
    assert [d.message for d in again.warnings] == [d.message for d in r.warnings]
    assert again.to_dict() == r.to_dict()


def test_csv_neutralises_formula_notes(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    path.write_text(
        'group,id,account,notes\ng,40823101,40823101,"=HYPERLINK(""x"")"\n', encoding="utf-8"
    )
    assert "\"'=HYPERLINK" in to_csv(load_roster(path, corrections=False))
