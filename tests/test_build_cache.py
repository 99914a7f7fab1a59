"""Incremental and atomic builds: hash-based cache hits and misses, failed builds change nothing."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from sitegen_helpers import mtimes, run_build, run_cli, snapshot, write_tree

from sitegen.errors import BuildError

TREE = {
    "index.md": "# Home\n\n[a](a.md)\n",
    "a.md": "# A\n\ntext a\n",
    "b.md": "# B\n\ntext b\n",
    "sec/index.md": "# Sec\n",
    "sec/c.md": "# C\n\ntext c\n",
}


@pytest.fixture()
def built(tmp_path: Path):
    src = write_tree(tmp_path / "src", TREE)
    out, cache = tmp_path / "site", tmp_path / "cache"
    first = run_build(src, out, cache_dir=cache)
    return src, out, cache, first


def test_cold_build_renders_everything(built):
    _src, _out, _cache, first = built
    assert first.pages == 5 and first.markdown_rendered == 5 and first.pages_rendered == 5


def test_noop_rebuild_renders_nothing_and_touches_no_file(built):
    src, out, cache, _ = built
    before = mtimes(out)
    again = run_build(src, out, cache_dir=cache)
    assert again.up_to_date
    assert mtimes(out) == before


def test_one_page_edit_rerenders_only_that_page(built):
    src, out, cache, _ = built
    before = mtimes(out)
    (src / "b.md").write_text("# B\n\ntext b, edited\n", encoding="utf-8")
    report = run_build(src, out, cache_dir=cache)
    assert report.markdown_rendered == 1
    assert report.pages_rendered == 1
    after = mtimes(out)
    changed = {rel for rel in after if after[rel] != before.get(rel)}
    assert changed == {"b.html", "assets/search-index.js"}
    assert "text b, edited" in (out / "b.html").read_text(encoding="utf-8")


def test_title_edit_rerenders_pages_that_show_it(built):
    src, out, cache, _ = built
    (src / "b.md").write_text("# B renamed\n\ntext b\n", encoding="utf-8")
    report = run_build(src, out, cache_dir=cache)
    assert report.markdown_rendered == 1
    # every page's menu shows top-level titles, so all top-level pages change; c.html (in sec,
    # whose menu also lists top level) too
    assert report.pages_rendered == 5
    assert "B renamed" in (out / "a.html").read_text(encoding="utf-8")


def test_fresh_checkout_with_new_mtimes_still_hits_the_cache(built, tmp_path):
    src, out, cache, _ = built
    for path in src.rglob("*.md"):
        os.utime(path, ns=(1, 1))  # a clone gives every file a new mtime
    report = run_build(src, out, cache_dir=cache)
    assert report.up_to_date


def test_moved_cache_with_new_output_renders_no_markdown(built, tmp_path):
    src, _out, cache, _ = built
    report = run_build(src, tmp_path / "elsewhere", cache_dir=cache)
    assert report.markdown_rendered == 0


def test_output_edited_by_hand_is_repaired(built):
    src, out, cache, _ = built
    (out / "a.html").write_text("vandalised", encoding="utf-8")
    report = run_build(src, out, cache_dir=cache)
    assert not report.up_to_date
    assert "text a" in (out / "a.html").read_text(encoding="utf-8")


def test_removed_page_disappears_from_output(built):
    src, out, cache, _ = built
    (src / "b.md").unlink()
    run_build(src, out, cache_dir=cache)
    assert not (out / "b.html").exists()


def test_failed_build_leaves_previous_site_intact(built):
    src, out, cache, _ = built
    before = snapshot(out)
    (src / "a.md").write_text("---\nweight: heavy\n---\n# A\n", encoding="utf-8")
    with pytest.raises(BuildError) as info:
        run_build(src, out, cache_dir=cache)
    assert any(
        d.file.endswith("a.md") and d.line == 2 and d.field == "weight"
        for d in info.value.diagnostics
    )
    assert snapshot(out) == before
    assert not any(p.name.startswith(".site.") for p in out.parent.iterdir())


@pytest.mark.parametrize("path", ["in place", "new folder"])
def test_crash_while_writing_leaves_previous_site_intact(built, monkeypatch, path):
    """Few changes are renamed into place, many go through a new folder that is swapped in;
    a crash before the renames (or while filling the new folder) leaves the site as it was."""
    src, out, cache, _ = built
    before = snapshot(out)
    (src / "a.md").write_text("# A\n\nnew text\n", encoding="utf-8")
    import sitegen.output as output

    def boom(*a, **k):
        raise OSError("disk full")

    if path == "in place":
        monkeypatch.setattr(output, "IN_PLACE_MIN_FILES", 0)
        monkeypatch.setattr(output, "_crash_point", boom)
    else:
        monkeypatch.setattr(output, "_few", lambda *a: False)
        monkeypatch.setattr(output, "copy_file", boom)
    with pytest.raises(OSError):
        run_build(src, out, cache_dir=cache)
    assert snapshot(out) == before
    assert sorted(p.name for p in out.parent.iterdir() if p.name.startswith(".")) == []
    monkeypatch.undo()
    run_build(src, out, cache_dir=cache)
    assert "new text" in (out / "a.html").read_text(encoding="utf-8")


def test_one_page_edit_of_a_big_site_touches_only_changed_files(built, monkeypatch):
    import sitegen.output as output

    monkeypatch.setattr(output, "IN_PLACE_MIN_FILES", 0)  # as for a site of 200 files or more
    src, out, cache, _ = built
    inode = (out / "b.html").stat().st_ino
    (src / "a.md").write_text("# A\n\nnew text\n", encoding="utf-8")
    report = run_build(src, out, cache_dir=cache)
    assert report.changed == ["a.html", "assets/search-index.js"]
    assert (out / "b.html").stat().st_ino == inode  # not copied into a new folder


def test_clean_rebuilds_everything(built):
    src, out, cache, _ = built
    report = run_build(src, out, cache_dir=cache, clean=True)
    assert report.markdown_rendered == 5


def test_corrupt_cache_means_cold_build(built):
    src, out, cache, _ = built
    (cache / "fragments.pickle").write_bytes(b"garbage")
    (cache / "state.json").write_text("{", encoding="utf-8")
    report = run_build(src, out, cache_dir=cache)
    assert report.markdown_rendered == 5
    assert snapshot(out)["a.html"]


def test_cli_errors_are_one_line_with_exit_codes(tmp_path):
    src = write_tree(
        tmp_path / "p",
        {"sitegen.yml": "title: x\nlanguge: en\nrosters: 3\n", "content/index.md": "# H\n"},
    )
    result = run_cli("build", "--source", str(src))
    assert result.returncode == 1
    assert "sitegen.yml:2: error: languge: unknown key" in result.stderr
    assert "sitegen.yml:3: error: rosters: must be a list" in result.stderr
    assert "Traceback" not in result.stderr
    assert run_cli("build", "--no-such-flag").returncode == 2
    assert run_cli("build", "--source", str(tmp_path / "nope")).returncode == 1
    for cmd in ("build", "serve", "check"):
        assert run_cli(cmd, "--help").returncode == 0


def test_check_command_reports_broken_links(tmp_path):
    out = write_tree(
        tmp_path / "site",
        {"index.html": '<a href="x.html">x</a>\n<img src="https://cdn.example/x.png">\n'},
    )
    result = run_cli("check", str(out))
    assert result.returncode == 1
    assert "index.html:1: 'x.html' not found" in result.stderr
    # external resources are checked for form only, as by `build --strict` (issue 13)
    assert "cdn.example" not in result.stderr
    shutil.rmtree(out)
