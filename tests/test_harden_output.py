"""Issue 15, items 3 and 4: the site never shares an inode with the sources; one build at a
time per output; a crash at any point of the publish step leaves a complete site, and the next
build cleans up after it (docs/security.md)."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import threading
from pathlib import Path

import pytest
from sitegen_helpers import REPO, run_build, run_cli, snapshot, write_tree

from sitegen import output
from sitegen.errors import BuildError

TREE = {"index.md": "# Home\n\n[a](a.txt)\n", "a.txt": "from the sources\n", "b.md": "# B\n"}


@pytest.fixture()
def project(tmp_path: Path) -> tuple[Path, Path]:
    return write_tree(tmp_path / "src", TREE), tmp_path / "site"


def test_appending_to_the_site_leaves_the_source_unchanged(project):
    src, out = project
    run_build(src, out)
    (src / "b.md").write_text("# B\n\nchanged\n", encoding="utf-8")
    run_build(src, out)  # a second build carries a.txt over from the first
    assert (out / "a.txt").stat().st_ino != (src / "a.txt").stat().st_ino
    with open(out / "a.txt", "a", encoding="utf-8") as fh:
        fh.write("x\n")
    assert (src / "a.txt").read_text(encoding="utf-8") == "from the sources\n"


def test_a_site_hard_linked_by_an_older_version_is_unlinked_by_the_next_build(project):
    src, out = project
    run_build(src, out)
    (out / "a.txt").unlink()
    (out / "a.txt").hardlink_to(src / "a.txt")  # what sitegen before issue 15 wrote
    run_build(src, out)
    assert (out / "a.txt").stat().st_ino != (src / "a.txt").stat().st_ino
    assert (src / "a.txt").stat().st_nlink == 1


def test_a_second_build_of_the_same_output_exits_with_a_clear_message(project):
    src, out = project
    errors: list[BaseException] = []

    def other_thread() -> None:
        try:
            run_build(src, out)
        except BaseException as exc:  # noqa: BLE001 (handed to the test)
            errors.append(exc)

    with output.output_lock(out.resolve()):
        result = run_cli("build", "--source", str(src), "--output", str(out))
        thread = threading.Thread(target=other_thread)
        thread.start()
        thread.join()
    assert len(errors) == 1 and isinstance(errors[0], BuildError)  # another thread: refused too
    assert result.returncode == 1 and "Traceback" not in result.stderr
    assert "another sitegen build (process " in result.stderr
    assert "is writing this site right now; run again when it has finished" in result.stderr
    run_build(src, out)  # the lock is gone with its holder
    assert not any(p.name.startswith(".site.") for p in out.parent.iterdir())


def test_concurrent_builds_do_not_collide(tmp_path):
    src = write_tree(
        tmp_path / "src",
        {**TREE, **{f"p{i}.md": f"# P{i}\n\n{'text ' * 200}\n" for i in range(40)}},
    )
    out = tmp_path / "site"
    procs = [
        subprocess.Popen(
            [sys.executable, "-m", "sitegen", "build", "--source", str(src), "--output", str(out)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for _ in range(4)
    ]
    results = [(p.wait(timeout=300), p.stderr.read()) for p in procs]
    for p in procs:
        p.stdout.close()
        p.stderr.close()
    for code, err in results:
        assert "Traceback" not in err
        assert code == 0 or (code == 1 and "another sitegen build" in err), err
    assert any(code == 0 for code, _ in results)
    assert (out / "p39.html").is_file() and (out / "a.txt").is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == [".sitegen-cache-site", "site", "src"]


def _crash(src: Path, out: Path, where: str, exchange: bool) -> subprocess.CompletedProcess:
    """A build killed (``os._exit``, no cleanup of any kind) at a point of the publish step."""
    code = textwrap.dedent(
        f"""
        import os, sys
        from pathlib import Path
        from sitegen import output
        from sitegen.build import BuildOptions, build
        if not {exchange!r}:
            output._exchange = lambda a, b: False  # a file system without RENAME_EXCHANGE
        def crash(point):
            if point == {where!r}:
                os._exit(9)
        output._crash_point = crash
        build(BuildOptions(source=Path({str(src)!r}), output=Path({str(out)!r})))
        """
    )
    return subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True)


def test_kill_between_the_two_renames_is_recovered_by_the_next_build(project):
    src, out = project
    run_build(src, out)
    before = snapshot(out)
    (src / "b.md").write_text("# B\n\nnew text\n", encoding="utf-8")
    assert _crash(src, out, "between renames", exchange=False).returncode == 9
    stranded = [p.name for p in out.parent.iterdir() if p.name.startswith(".site.")]
    assert not out.exists() and ".site.sitegen-previous" in stranded
    assert output.recover(out) == [
        f"recovered the previous site into {out}",
        *(f"removed {n}" for n in stranded if "building" in n),
    ]
    assert snapshot(out) == before  # the last complete site, back in place
    run_build(src, out)
    assert "new text" in (out / "b.html").read_text(encoding="utf-8")
    assert not any(p.name.startswith(".site.") for p in out.parent.iterdir())


def test_the_next_build_recovers_a_stranded_site_by_itself(project):
    src, out = project
    run_build(src, out)
    (src / "b.md").write_text("# B\n\nnew text\n", encoding="utf-8")
    assert _crash(src, out, "between renames", exchange=False).returncode == 9
    assert not out.exists()
    report = run_build(src, out)
    assert "new text" in (out / "b.html").read_text(encoding="utf-8") and report.changed
    assert not any(p.name.startswith(".site.") for p in out.parent.iterdir())


def test_with_an_atomic_exchange_a_kill_never_leaves_the_output_missing(project):
    src, out = project
    run_build(src, out)
    (src / "b.md").write_text("# B\n\nnew text\n", encoding="utf-8")
    probe_a, probe_b = out.parent / "probe-a", out.parent / "probe-b"
    probe_a.mkdir()
    probe_b.mkdir()
    exchanged = output._exchange(probe_a, probe_b)
    probe_a.rmdir()
    probe_b.rmdir()
    if not exchanged:
        pytest.skip("this file system has no RENAME_EXCHANGE: the two-rename path is used")
    assert _crash(src, out, "after exchange", exchange=True).returncode == 9
    assert "new text" in (out / "b.html").read_text(encoding="utf-8")  # complete, and new
    assert any(".sitegen-building-" in p.name for p in out.parent.iterdir())  # the old site
    run_build(src, out)
    assert not any(p.name.startswith(".site.") for p in out.parent.iterdir())


def test_stale_temporary_folders_of_dead_builds_are_removed(project):
    src, out = project
    for name in (".site.sitegen-building-99999", ".site.building-99998"):
        (out.parent / name / "x").mkdir(parents=True)
    run_build(src, out)
    assert sorted(p.name for p in out.parent.iterdir()) == [".sitegen-cache-site", "site", "src"]


def test_a_failure_while_writing_leaves_the_old_site_and_no_leftovers(project, monkeypatch):
    src, out = project
    run_build(src, out)
    before = snapshot(out)
    (src / "b.md").write_text("# B\n\nnew text\n", encoding="utf-8")

    def full(*_args: object) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(output, "copy_file", full)
    with pytest.raises(OSError):
        run_build(src, out)
    assert snapshot(out) == before
    assert sorted(p.name for p in out.parent.iterdir()) == [".sitegen-cache-site", "site", "src"]


def test_a_kill_during_an_in_place_update_is_completed_by_the_next_build(project, tmp_path):
    """Big sites take a few changes in place, file by file (docs/performance.md): killed
    halfway through the renames, the site mixes complete old and new files; the next build
    makes it exactly what a clean build of the new sources makes."""
    src, out = project
    run_build(src, out)
    (src / "index.md").write_text(TREE["index.md"] + "\nnew text\n", encoding="utf-8")
    (src / "b.md").write_text(TREE["b.md"] + "\nnew text\n", encoding="utf-8")
    code = textwrap.dedent(
        f"""
        import os
        from pathlib import Path
        from sitegen import output
        from sitegen.build import BuildOptions, build
        output.IN_PLACE_MIN_FILES = 0  # as for a site of 200 files or more
        real_replace = os.replace
        def replace(a, b):
            if Path(b).name == "index.html":
                os._exit(9)  # b.html renamed over its old version, index.html not yet
            real_replace(a, b)
        os.replace = replace
        build(BuildOptions(source=Path({str(src)!r}), output=Path({str(out)!r})))
        """
    )
    crashed = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True)
    assert crashed.returncode == 9, crashed.stderr.decode()[-2000:]
    assert "new text" in (out / "b.html").read_text(encoding="utf-8")  # halfway: new
    assert "new text" not in (out / "index.html").read_text(encoding="utf-8")  # still old
    run_build(src, out)
    clean = tmp_path / "clean"
    run_build(src, clean)
    assert snapshot(out) == snapshot(clean)
    assert not any(p.name.startswith(".site.") for p in out.parent.iterdir())
