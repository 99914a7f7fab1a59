"""One walk of the content folder (sitegen.source_stats.Walk): the scan that reads it, the
no-op build's stat walk and serve's change snapshot see the same files by the same rules."""

from __future__ import annotations

from sitegen_helpers import write_tree

from sitegen.content import scan
from sitegen.errors import Diagnostics
from sitegen.source_stats import snapshot, stat_walk

TREE = {
    "index.md": "# Home\n",
    "b/index.md": "# B\n",
    "b/z.png": b"png",
    "b/c/deep.md": "# Deep\n",
    "a.md": "# A\n",
    ".hidden.md": "# not published\n",
    "notes.md~": "an editor's backup\n",
    ".git/config": "x",
    "node_modules/x.js": "x",
    "b/__pycache__/m.pyc": b"x",
    "site/index.html": "<p>the output</p>",
}
SEEN = ["a.md", "index.md", "b/index.md", "b/z.png", "b/c/deep.md"]


def test_scan_stat_walk_and_snapshot_see_the_same_files_in_the_same_order(tmp_path):
    root = write_tree(tmp_path / "content", TREE)
    exclude = {root / "site"}
    tree = scan(root, Diagnostics(), exclude=exclude)
    assert list(tree.stats) == SEEN  # a folder's files, then its folders, by name
    walked = stat_walk(root, exclude)
    assert walked is not None and sorted(walked) == sorted(SEEN)
    assert walked == tree.stats
    assert [rel for rel, _size, _mtime in snapshot(root, exclude)] == SEEN


def test_a_symlink_is_judged_by_each_walker(tmp_path):
    root = write_tree(tmp_path / "content", {"a.md": "# A\n", "b/x.md": "# X\n"})
    (root / "link").symlink_to(root / "b", target_is_directory=True)
    tree = scan(root, Diagnostics())
    assert sorted(tree.stats) == ["a.md", "b/x.md", "link/x.md"]  # followed inside the folder
    assert stat_walk(root, set()) is None  # left to the scan
    assert "link" in [rel for rel, _s, _m in snapshot(root, set())]  # a change shows
