"""Object paths as ``sim.getObject`` resolves them for a ZeroMQ client, on hand-made trees."""

from __future__ import annotations

import pytest

from sims.remote_api.zmq.paths import Entry, PathError, Tree, full_path, parse, resolve

# /robot
#   body
#     joint          (alias "joint")
#       wheel
#     joint#0 ...    (second "joint" under body: name joint#1, alias joint)
#   sensor
# /robot#0           (a second robot, V-REP-era names: no alias)
#   joint#2
# /Floor
TREE = [
    Entry(1, "robot", "robot", None),
    Entry(2, "body", "body", 1),
    Entry(3, "joint", "joint", 2, "joint"),
    Entry(4, "wheel", "wheel", 3),
    Entry(5, "joint#1", "joint", 2, "joint"),
    Entry(6, "sensor", "sensor", 1, "proximity_sensor"),
    Entry(7, "robot#0", "", None),
    Entry(8, "joint#2", "", 7, "joint"),
    Entry(9, "Floor", "Floor", None),
]


@pytest.mark.parametrize(
    "path, handle",
    [
        ("/robot", 1),
        ("/robot/body", 2),
        ("/robot/body/joint", 3),
        ("/robot/joint", 3),  # a simplified path skips levels
        ("/robot/joint/wheel", 4),
        ("/robot/body/joint[1]", 5),  # the second "joint" among its siblings
        ("/robot/joint{1}", 5),  # the second match overall
        ("/joint{2}", 8),  # the third object with alias "joint" in the scene
        ("/robot/joint[0]", 3),
        ("/Floor", 9),
        ("./Floor", 9),  # a remote client has no script object: ./ is the scene root
        (":/robot/sensor", 6),
        ("/robot/sen*", 6),
        ("/*/wheel", 4),
        ("/rob?t/body", 2),
        ("/robot/nothing", None),
        ("/robot/body/joint[2]", None),
        ("/Floor/robot", None),  # the floor has no children
        ("/robot/Joint", None),  # aliases are case-sensitive
    ],
)
def test_paths_resolve_like_coppeliasim(path, handle):
    assert resolve(TREE, path) == handle


def test_an_old_scene_without_aliases_uses_names_without_suffix():
    # "robot#0" has no alias: its alias is "robot", so /robot matches both; the first wins,
    # and {1} picks the V-REP-era one.
    assert resolve(TREE, "/robot{1}") == 7
    assert resolve(TREE, "/robot{1}/joint") == 8


def test_index_option_picks_the_nth_match():
    # both robots answer to /robot, so the third match is the V-REP-era robot's joint
    assert [resolve(TREE, "/robot/joint", index=i) for i in range(4)] == [3, 5, 8, None]
    assert [resolve(TREE, "/joint", index=i) for i in range(3)] == [3, 5, 8]


def test_old_style_names_are_looked_up_by_name():
    assert resolve(TREE, "joint#1") == 5
    assert resolve(TREE, "robot#") == 1
    assert resolve(TREE, "Floor#0") == 9
    assert resolve(TREE, "joint#7") is None
    assert resolve(TREE, "sensor") == 6


@pytest.mark.parametrize("path", ["/", "//robot", "/robot/", "/robot/[0]", "/a[x]", ".", "::"])
def test_malformed_paths_are_errors(path):
    with pytest.raises(PathError):
        parse(path) if path.startswith("/") else resolve(TREE, path)


def test_matches_come_in_coppeliasims_search_order():
    # CoppeliaSim (getObjectFromPath) tries a level's children before their subtrees: the
    # shallow "target" wins over the deeper one listed before it
    tree = [
        Entry(1, "a", "a", None),
        Entry(2, "x", "x", 1),
        Entry(3, "deep", "target", 2),
        Entry(4, "shallow", "target", 1),
    ]
    assert resolve(tree, "/a/target") == 4
    assert resolve(tree, "/a/target{1}") == 3
    assert resolve(tree, "/a/target[0]") == 4  # first "target" among a's own children
    assert resolve(tree, "/a/x/target") == 3


def test_full_path_names_every_level():
    tree = Tree(TREE)
    assert full_path(tree, 4) == "/robot/body/joint/wheel"
    assert full_path(tree, 8) == "/robot/joint"
    assert resolve(tree, full_path(tree, 6)) == 6
