"""The course's real roster: the numbers and the link set the teacher relies on.

The reference is the course script itself (`task1_roster_links.py`), run on a
copy of the file; our links must be exactly the hrefs it prints.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from roster import load_roster
from roster.emit import to_html

SHARED = Path(__file__).resolve().parents[1].parent / "shared"
REAL = SHARED / "data" / "stage3_2a.txt"
SCRIPT = SHARED / "seeds" / "scripts" / "task1_roster_links.py"
FIXTURES = Path(__file__).parent / "fixtures" / "roster"
CORRECTIONS = FIXTURES / "stage3_2a.corrections.yml"

pytestmark = pytest.mark.needs_shared("data", "stage3_2a.txt")

HREF = re.compile(r'href="([^"]*)"')


@pytest.fixture(scope="module")
def script_hrefs(tmp_path_factory: pytest.TempPathFactory) -> list[str]:
    """Run the course script on a copy of the roster and collect the hrefs it prints."""
    work = tmp_path_factory.mktemp("script")
    shutil.copy(REAL, work / "stage3_2a.txt")
    done = subprocess.run(
        [sys.executable, str(SCRIPT)],
        cwd=work,
        capture_output=True,
        text=True,
        timeout=60,
        check=True,
    )
    return HREF.findall(done.stdout)


@pytest.fixture(scope="module")
def result():
    return load_roster(REAL, corrections=CORRECTIONS)


def test_real_roster_has_6_groups_and_46_members(result) -> None:
    groups = result.roster.groups
    assert len(groups) == 6
    assert [len(g.members) for g in groups] == [8, 8, 6, 8, 8, 8]
    assert len(result.roster.members) == 46
    assert len({m.id for m in result.roster.members}) == 46
    assert result.errors == []


def test_link_set_equals_course_script_output(result, script_hrefs: list[str]) -> None:
    assert len(script_hrefs) == 2 * (6 + 46)
    ours = HREF.findall(to_html(result))
    assert sorted(ours) == sorted(script_hrefs)
    assert len(set(ours)) == len(ours)  # no link twice


def test_links_in_same_order_as_script(result, script_hrefs: list[str]) -> None:
    """Group links then its members, group by group, as the script printed them."""
    assert HREF.findall(to_html(result)) == script_hrefs


def test_to_dict_links_equal_script_links(result, script_hrefs: list[str]) -> None:
    data = result.to_dict()
    urls = []
    for g in data["groups"]:
        urls += [g["repo_url"], g["site_url"]]
        for m in g["members"]:
            urls += [m["repo_url"], m["site_url"]]
    assert urls == script_hrefs


def test_script_fixes_are_reported_as_corrections(result) -> None:
    applied = [d.message for d in result.corrections_applied]
    renames = [m for m in applied if m.startswith("group name")]
    assert len(renames) == 6
    assert "group name 'stage3_ag1' -> 'stage3-ag1'" in renames[0]
    assert any("alias: account of 40823112 is already 'a40823112'" in m for m in applied)
    # Every applied correction points at the roster line and field it changed.
    assert all(d.file == str(REAL) and d.line >= 1 and d.field for d in result.corrections_applied)


def test_typo_already_fixed_in_real_file_is_an_unmatched_warning(result) -> None:
    unmatched = [d for d in result.warnings if "matched nothing" in d.message]
    assert len(unmatched) == 1
    assert unmatched[0].file == str(CORRECTIONS)
    assert unmatched[0].line == 3
    assert unmatched[0].field == "typos.4823122"


def test_ids_from_other_years_are_warned(result) -> None:
    """Once, naming both (issue 30: one warning per kind of anomaly, not one per line)."""
    (shape,) = [d for d in result.warnings if "look unlike" in d.message]
    assert shape.message.startswith("2 ids look unlike the others")
    assert "40623121 (line 2), 40523252 (line 3)" in shape.message
    odd = sorted(d.message.split()[1] for d in result.infos if "looks unlike" in d.message)
    assert odd == ["40523252", "40623121"]


def test_without_corrections_the_id_with_a_letter_is_noted_not_warned() -> None:
    """`a40823112` is the id with a letter added, the usual account when the bare id was
    taken: an info note (issue 30), not a warning asking for an alias."""
    bare = load_roster(REAL, corrections=False)
    assert bare.errors == []
    assert not [d for d in bare.warnings if "40823112" in d.message]
    msgs = [str(d) for d in bare.infos if "a40823112" in d.message]
    assert msgs == [
        f"{REAL}:1: info: member 2 account (col 5): "
        "account 'a40823112' is the id 40823112 with letters added"
    ]
    assert [g.name for g in bare.roster.groups][0] == "stage3_ag1"


def test_group_repo_and_site_owned_by_first_member(result) -> None:
    g = result.roster.groups[2]
    assert g.name == g.slug == "stage3-ag3"
    assert g.leader == "40823119"
    d = result.to_dict()["groups"][2]
    assert d["repo_url"] == "https://github.com/40823119/stage3-ag3"
    assert d["site_url"] == "https://40823119.github.io/stage3-ag3"
