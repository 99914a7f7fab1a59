"""diff(old, new): the changes a teacher checks before republishing a roster."""

from __future__ import annotations

from pathlib import Path

from roster import diff, load_roster


def roster(
    *groups: tuple[str, list[tuple[str, str]]], leaders: dict[str, str] | None = None
) -> dict:
    leaders = leaders or {}
    return {
        "groups": [
            {
                "name": name,
                "slug": name,
                "leader": leaders.get(name, members[0][0]),
                "repo_url": None,
                "site_url": None,
                "members": [
                    {"id": i, "account": a, "repo_url": None, "site_url": None, "notes": []}
                    for i, a in members
                ],
            }
            for name, members in groups
        ]
    }


A = ("a", [("1", "1"), ("2", "2"), ("3", "3")])
B = ("b", [("4", "4"), ("5", "5")])


def test_no_changes_and_each_single_edit_is_one_line() -> None:
    """Nothing changed -> no lines; reordering is not a change. Each single edit of the same
    roster is exactly its one line, so a diff that never reports anything fails here."""
    same = roster(A, B, leaders={"a": "1", "b": "4"})
    assert diff(same, roster(A, B, leaders={"a": "1", "b": "4"})) == []
    shuffled = ("a", [("3", "3"), ("1", "1"), ("2", "2")])
    assert diff(same, roster(B, shuffled, leaders={"a": "1", "b": "4"})) == []
    edits = {
        "account changed: 5: 5 -> x5": roster(A, ("b", [("4", "4"), ("5", "x5")])),
        "leader changed in b: 4 -> 5": roster(A, B, leaders={"a": "1", "b": "5"}),
        "member removed: 3 (was in a)": roster(("a", [("1", "1"), ("2", "2")]), B),
        "member added: 7 (7) in b": roster(A, ("b", [("4", "4"), ("5", "5"), ("7", "7")])),
    }
    for line, edited in edits.items():
        assert diff(same, edited) == [line]


def test_member_added_removed_moved_and_account_changed() -> None:
    old = roster(A, B)
    new = roster(
        ("a", [("1", "1"), ("2", "x2")]), ("b", [("4", "4"), ("5", "5"), ("3", "3"), ("6", "6")])
    )
    # group-level lines first, then one line per change, ordered by student id
    assert diff(old, new) == [
        "account changed: 2: 2 -> x2",
        "member moved: 3 from a to b",
        "member added: 6 (6) in b",
    ]
    assert diff(new, old) == [
        "account changed: 2: x2 -> 2",
        "member moved: 3 from b to a",
        "member removed: 6 (was in b)",
    ]


def test_groups_added_and_removed() -> None:
    assert diff(roster(A), roster(A, B)) == [
        "group added: b (2 members)",
        "member added: 4 (4) in b",
        "member added: 5 (5) in b",
    ]
    assert diff(roster(A, B), roster(A))[0] == "group removed: b (2 members)"


def test_renamed_group_is_not_every_member_moving() -> None:
    renamed = ("a-new", [("1", "1"), ("2", "2"), ("3", "3")])
    assert diff(roster(A, B), roster(renamed, B)) == ["group renamed: a -> a-new"]


def test_leader_change() -> None:
    assert diff(roster(A), roster(A, leaders={"a": "2"})) == ["leader changed in a: 1 -> 2"]


def test_diff_of_real_loads_after_corrections(tmp_path: Path) -> None:
    path = tmp_path / "r.txt"
    path.write_text("g_1\t40823101\t40823101\t40823112\t40823112\n", encoding="utf-8")
    fix = tmp_path / "fix.yml"
    fix.write_text(
        'aliases: {"40823112": a40823112}\ngroup_names: [{replace: "_", with: "-"}]\n',
        encoding="utf-8",
    )
    before = load_roster(path, corrections=False).to_dict()
    after = load_roster(path, corrections=fix).to_dict()
    assert diff(before, after) == [
        "group renamed: g_1 -> g-1",
        "account changed: 40823112: 40823112 -> a40823112",
    ]
