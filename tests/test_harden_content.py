"""Issue 15, items 1 and 5: nothing outside the content folder reaches a site; deep or huge
input ends in a clear error naming the file, never a traceback (docs/security.md)."""

from __future__ import annotations

import functools
import os
import shutil
import tempfile
import threading
import urllib.error
import urllib.request
from http.server import ThreadingHTTPServer
from pathlib import Path

import pytest
from sitegen_helpers import run_build, run_cli, write_tree

from sitegen import content
from sitegen.check import check_site
from sitegen.errors import BuildError

SECRET = "root:x:0:0:secret outside the content folder\n"


@pytest.fixture()
def project(tmp_path: Path) -> tuple[Path, Path, Path]:
    """(content folder, output folder, a secret file outside the content folder)"""
    src = write_tree(tmp_path / "src", {"index.md": "# Home\n", "a.txt": "a\n"})
    secret = tmp_path / "private" / "passwd"
    secret.parent.mkdir()
    secret.write_text(SECRET, encoding="utf-8")
    return src, tmp_path / "site", secret


def _no_secret_in(folder: Path) -> bool:
    if not folder.exists():
        return True
    return not any(
        p.is_symlink() or (p.is_file() and SECRET.encode() in p.read_bytes())
        for p in folder.rglob("*")
    )


@pytest.mark.parametrize("link_to_folder", [False, True])
def test_symlink_out_of_the_content_folder_is_an_error_naming_the_link(project, link_to_folder):
    src, out, secret = project
    (src / "leak.txt").symlink_to(secret.parent if link_to_folder else secret)
    result = run_cli("build", "--source", str(src), "--output", str(out))
    assert result.returncode == 1
    assert "Traceback" not in result.stderr
    assert "leak.txt: error: symlink: points outside the content folder" in result.stderr
    assert _no_secret_in(out)


def test_symlink_inside_the_content_folder_is_published_as_a_copy(project):
    src, out, _ = project
    (src / "docs").mkdir()
    (src / "docs" / "alias.txt").symlink_to("../a.txt")
    (src / "mirror").symlink_to("docs", target_is_directory=True)
    run_build(src, out)
    for rel in ("docs/alias.txt", "mirror/alias.txt"):
        assert not (out / rel).is_symlink() and (out / rel).read_text() == "a\n"
    assert not [p for p in check_site(out) if "symlink" in p]


def test_symlink_loop_and_broken_link_are_errors(project):
    src, out, _ = project
    (src / "sub").mkdir()
    (src / "sub" / "up").symlink_to("..", target_is_directory=True)
    (src / "gone.txt").symlink_to("nowhere.txt")
    with pytest.raises(BuildError) as info:
        run_build(src, out)
    found = {(d.file, d.field, d.message.split(" (")[0]) for d in info.value.diagnostics}
    assert ("sub/up", "symlink", "points to a folder that contains it") in found
    assert ("gone.txt", "symlink", "points to nothing") in found


def test_check_flags_any_symlink_in_a_built_site(project):
    src, out, secret = project
    run_build(src, out)
    (out / "leak.txt").symlink_to(secret)
    problems = check_site(out)
    assert any(p.startswith("leak.txt: is a symlink") for p in problems), problems


def test_serve_does_not_serve_through_a_symlink_out_of_the_site(project):
    from sitegen import serve

    src, out, secret = project
    run_build(src, out)
    (out / "leak.txt").symlink_to(secret)
    (out / "inside.txt").symlink_to("a.txt")
    serve._Handler.state = serve._State()
    handler = functools.partial(serve._Handler, directory=str(out))
    server = ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    base = f"http://127.0.0.1:{server.server_address[1]}/"
    try:
        with pytest.raises(urllib.error.HTTPError) as info:
            urllib.request.urlopen(base + "leak.txt", timeout=10)
        assert info.value.code == 404
        with urllib.request.urlopen(base + "inside.txt", timeout=10) as resp:
            assert resp.read() == b"a\n"
    finally:
        server.shutdown()
        server.server_close()


def _nest(root: Path, depth: int) -> None:
    """``root/d/d/.../d`` ``depth`` folders deep, made through folder handles: the full path is
    far longer than the system allows a path name to be."""
    fd = os.open(root, os.O_RDONLY)
    try:
        for _ in range(depth):
            os.mkdir("d", dir_fd=fd)
            child = os.open("d", os.O_RDONLY, dir_fd=fd)
            os.close(fd)
            fd = child
    finally:
        os.close(fd)


def _unnest(root: Path) -> None:
    """Remove what :func:`_nest` made without recursion, one folder handle at a time."""
    fd, depth = os.open(root, os.O_RDONLY), 0
    while True:
        try:
            child = os.open("d", os.O_RDONLY, dir_fd=fd)
        except FileNotFoundError:
            break
        os.close(fd)
        fd, depth = child, depth + 1
    for _ in range(depth):
        parent = os.open("..", os.O_RDONLY, dir_fd=fd)
        os.close(fd)
        fd = parent
        os.rmdir("d", dir_fd=fd)
    os.close(fd)


@pytest.fixture()
def fast_tmp(tmp_path: Path):
    """A folder in memory where there is one (/dev/shm): ten thousand folders one inside the
    other take a minute to make and remove on a loaded disk, a second in memory."""
    shm = Path("/dev/shm")
    if shm.is_dir() and os.access(shm, os.W_OK):
        folder = Path(tempfile.mkdtemp(prefix="sitegen-harden-", dir=shm))
        yield folder
        shutil.rmtree(folder, ignore_errors=True)
    else:
        yield tmp_path


def test_ten_thousand_nested_folders_end_in_a_clear_error(fast_tmp):
    src = write_tree(fast_tmp / "src", {"index.md": "# Home\n"})
    _nest(src, 10_000)
    try:
        result = run_cli("build", "--source", str(src), "--output", str(fast_tmp / "site"))
    finally:
        _unnest(src)
    assert "Traceback" not in result.stderr and "RecursionError" not in result.stderr
    assert result.returncode == 1
    deepest = "/".join(["d"] * (content.MAX_DEPTH + 1))
    assert f"{deepest}: error: folders nest deeper than {content.MAX_DEPTH} levels" in (
        result.stderr
    )


def test_the_depth_limit_leaves_shallower_folders_alone(tmp_path):
    rel = "/".join(["d"] * content.MAX_DEPTH)
    src = write_tree(tmp_path / "src", {"index.md": "# Home\n", f"{rel}/deep.md": "# Deep\n"})
    report = run_build(src, tmp_path / "site")
    assert report.pages >= 2 and any(p.name == "deep.html" for p in (tmp_path / "site").rglob("*"))


def test_files_above_the_size_limits_are_errors_naming_the_file(tmp_path):
    src = write_tree(tmp_path / "src", {"index.md": "# Home\n"})
    with open(src / "huge.md", "wb") as fh:  # sparse: nothing is written to disk
        fh.truncate(content.MAX_PAGE_BYTES + 1)
    with open(src / "video.webm", "wb") as fh:
        fh.truncate(content.MAX_ASSET_BYTES + 1)
    with open(src / "fits.bin", "wb") as fh:
        fh.truncate(1 << 20)
    with pytest.raises(BuildError) as info:
        run_build(src, tmp_path / "site")
    messages = {d.file: d.message for d in info.value.diagnostics}
    assert set(messages) == {"huge.md", "video.webm"}
    assert messages["huge.md"] == "a Markdown page larger than the limit of 8 MiB; not published"
    assert messages["video.webm"] == "a file larger than the limit of 100 MiB; not published"


def test_a_fifo_in_the_content_folder_is_reported_not_read(tmp_path):
    src = write_tree(tmp_path / "src", {"index.md": "# Home\n"})
    os.mkfifo(src / "pipe.txt")  # reading it would block the build forever
    with pytest.raises(BuildError) as info:
        run_build(src, tmp_path / "site")
    assert [(d.file, d.message) for d in info.value.diagnostics] == [
        ("pipe.txt", "not a regular file or folder; not published")
    ]
