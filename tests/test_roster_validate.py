"""Validation: errors block publishing (wrong groups, unsafe links); warnings flag likely typos."""

from __future__ import annotations

from pathlib import Path

import pytest

from roster import load_roster


def load(tmp_path: Path, text: str, corrections: str | None = None, **kw):
    path = tmp_path / "r.txt"
    path.write_text(text, encoding="utf-8")
    fix: Path | bool = False
    if corrections is not None:
        fix = tmp_path / "fix.yml"
        fix.write_text(corrections, encoding="utf-8")
    return load_roster(path, corrections=fix, **kw)


def only(diags, text: str):
    found = [d for d in diags if text in d.message]
    assert len(found) == 1, [str(d) for d in diags]
    return found[0]


# --- errors -------------------------------------------------------------------------------


def test_student_in_two_groups(tmp_path: Path) -> None:
    r = load(tmp_path, "a\t40823101\t40823101\nb\t40823102\t40823102\t40823101\t40823101\n")
    e = only(r.errors, "in two groups")
    assert (e.line, e.field) == (2, "member 2 id (col 4)")
    assert "'a' (line 1)" in e.message


def test_student_twice_in_one_group(tmp_path: Path) -> None:
    r = load(tmp_path, "a\t40823101\t40823101\t40823101\t40823101\n")
    assert only(r.errors, "listed twice").line == 1


def test_two_groups_with_the_same_corrected_name(tmp_path: Path) -> None:
    text = "g_1\t40823101\t40823101\ng-1\t40823102\t40823102\n"
    assert load(tmp_path, text).errors == []
    r = load(tmp_path, text, corrections='group_names: [{replace: "_", with: "-"}]\n')
    e = only(r.errors, "two groups named 'g-1'")
    assert e.line == 2 and "line 1" in e.message


def test_names_differing_only_by_case_or_space_share_a_slug(tmp_path: Path) -> None:
    r = load(tmp_path, "Team A\t40823101\t40823101\nteam-a\t40823102\t40823102\n")
    assert only(r.errors, "same slug").line == 2
    assert r.roster.groups[0].slug == "Team-A"


def test_group_with_no_members(tmp_path: Path) -> None:
    r = load(tmp_path, "a\t40823101\t40823101\nempty\t\t\t\t\n")
    e = only(r.errors, "has no members")
    assert (e.line, e.field) == (2, "group name (col 1)")
    assert r.to_dict()["groups"][1]["repo_url"] is None


@pytest.mark.parametrize(
    "account, why",
    [
        ("javascript:alert(1)", "contains ':'"),
        ("../x", "contains '..'"),
        ("a/b", "contains '/'"),
        ('x"onmouseover="y', "contains '\"'"),
        ("-x", "must start with a letter or digit"),
        ("x" * 101, "longer than 100"),
    ],
)
def test_unsafe_account_is_an_error_and_never_a_link(
    tmp_path: Path, account: str, why: str
) -> None:
    r = load(tmp_path, f"g\t40823101\t40823101\t40823102\t{account}\n")
    e = only(r.errors, why)
    assert (e.line, e.field) == (1, "member 2 account (col 5)")
    member = r.to_dict()["groups"][0]["members"][1]
    assert member["repo_url"] is None and member["site_url"] is None


def test_unsafe_alias_is_caught_too(tmp_path: Path) -> None:
    r = load(tmp_path, "g\t40823101\t40823101\n", corrections='aliases: {"40823101": "../evil"}\n')
    assert only(r.errors, "contains '..'").field == "member 1 account (col 3)"


@pytest.mark.parametrize("name", ["..", "第一組", "a.(b)"])
def test_unsafe_slug_is_an_error(tmp_path: Path, name: str) -> None:
    r = load(tmp_path, f"{name}\t40823101\t40823101\n")
    assert r.errors
    assert r.to_dict()["groups"][0]["repo_url"] is None


def test_unsafe_course_repo_is_an_error(tmp_path: Path) -> None:
    r = load(tmp_path, "g\t40823101\t40823101\n", course_repo="../x")
    assert only(r.errors, "course repo").field == "course_repo"
    assert r.to_dict()["groups"][0]["members"][0]["repo_url"] is None


# --- warnings -----------------------------------------------------------------------------


def test_id_with_different_prefix_or_length_is_warned(tmp_path: Path) -> None:
    text = "g\t40823101\t40823101\t40823102\t40823102\t40623103\t40623103\t4082310\t4082310\n"
    r = load(tmp_path, text)
    assert r.errors == []
    (summary,) = [d for d in r.warnings if "look unlike" in d.message]
    assert summary.message.startswith("2 ids look unlike the others")
    warned = {d.message.split()[1]: d.message for d in r.infos if "looks unlike" in d.message}
    assert set(warned) == {"40623103", "4082310"}
    assert "starts with '406' where most ids start with '408'" in warned["40623103"]
    assert "7 characters where most ids have 8" in warned["4082310"]


def test_no_shape_warning_without_a_clear_majority(tmp_path: Path) -> None:
    r = load(tmp_path, "g\t40823101\t40823101\tB1234\tB1234\n")
    assert not [d for d in r.warnings if "looks unlike" in d.message]


@pytest.mark.parametrize("account", ["a_b", "a--b", "ab-", "x" * 40, "a.b"])
def test_account_breaking_github_rules_is_a_warning_not_an_error(
    tmp_path: Path, account: str
) -> None:
    r = load(
        tmp_path, f"g\t40823101\t{account}\n", corrections=f'aliases: {{"40823101": "{account}"}}\n'
    )
    assert r.errors == []
    only(r.warnings, "GitHub username")
    assert (
        r.to_dict()["groups"][0]["members"][0]["repo_url"] == f"https://github.com/{account}/cd2021"
    )


def test_account_differing_from_id_without_alias(tmp_path: Path) -> None:
    r = load(tmp_path, "g\t40823101\tann-lee\n")
    w = only(r.warnings, "differs from id")
    assert w.field == "member 1 account (col 3)"
    assert (
        load(
            tmp_path, "g\t40823101\tann-lee\n", corrections='aliases: {"40823101": ann-lee}\n'
        ).warnings
        == []
    )


def test_account_that_is_another_id_hints_at_a_missing_column(tmp_path: Path) -> None:
    # one account among ordinary ones: a paired file with a slip, warned per member
    r = load(tmp_path, "g\t40823101\t40823102\t40823103\t40823103\t40823105\tann\n")
    assert r.layout == "paired"
    assert "is a column missing" in only(r.warnings, "differs from id 40823101").message


def test_shared_account_is_warned(tmp_path: Path) -> None:
    r = load(
        tmp_path,
        "g\t40823101\tsam\t40823102\tsam\n",
        corrections='aliases: {"40823101": sam, "40823102": sam}\n',
    )
    assert only(r.warnings, "also used by 40823101").line == 1
