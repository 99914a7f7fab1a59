"""``sitegen serve`` for authors: the address is checked before building (one-line errors),
``--dev-addr``, missing pages answered with the site's 404 page, fixed errors announced, and
``-q``/``-v`` on the site commands."""

from __future__ import annotations

import re
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest
from sitegen_helpers import run_cli, write_tree

from sitegen.serve import AddressError, parse_dev_addr


def _serve(src: Path, out: Path, *extra: str) -> subprocess.Popen:
    return subprocess.Popen(
        [
            sys.executable,
            "-m",
            "sitegen",
            "serve",
            "--source",
            str(src),
            "--output",
            str(out),
            *extra,
        ],
        stderr=subprocess.PIPE,
        text=True,
    )


def _address(proc: subprocess.Popen, seen: list[str]) -> str:
    deadline = time.time() + 60
    while time.time() < deadline:
        line = proc.stderr.readline()
        seen.append(line)
        m = re.search(r"(http://127\.0\.0\.1:\d+/)", line)
        if m:
            return m.group(1)
    raise AssertionError(f"server did not report its address: {seen}")


def _wait_for(proc: subprocess.Popen, pattern: str, seen: list[str]) -> str:
    deadline = time.time() + 60
    while time.time() < deadline:
        line = proc.stderr.readline()
        seen.append(line)
        if re.search(pattern, line):
            return line
    raise AssertionError(f"no line matching {pattern!r}: {seen}")


def test_port_in_use_is_one_line_before_any_build(tmp_path):
    src = write_tree(tmp_path / "s", {"index.md": "# Home\n"})
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        result = run_cli(
            "serve", "--source", str(src), "--output", str(tmp_path / "o"), "--port", str(port)
        )
    assert result.returncode == 1
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "in use" in lines[0] and "--dev-addr" in lines[0], result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "o").exists()  # checked before building


@pytest.mark.parametrize(
    "args, words",
    [
        (["--port", "70000"], "out of range"),
        (["--port", "-1"], "out of range"),
        (["--port", "http"], "not a number"),
        (["--dev-addr", "127.0.0.1"], "HOST:PORT"),
        (["--dev-addr", "0.0.0.0:8000"], "not a loopback address"),
        (["--dev-addr", "example.org:8000"], "not an IP address"),
    ],
)
def test_bad_address_is_a_usage_error(tmp_path, args, words):
    src = write_tree(tmp_path / "s", {"index.md": "# Home\n"})
    result = run_cli("serve", "--source", str(src), "--output", str(tmp_path / "o"), *args)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and words in result.stderr, result.stderr
    assert not (tmp_path / "o").exists()


def test_dev_addr_parsing():
    assert parse_dev_addr("127.0.0.1:8001") == ("127.0.0.1", 8001)
    assert parse_dev_addr("localhost:0") == ("127.0.0.1", 0)
    assert parse_dev_addr("[::1]:8002") == ("::1", 8002)
    with pytest.raises(AddressError):
        parse_dev_addr("192.168.1.5:8000")


def test_missing_pages_get_the_404_page_and_fixed_errors_are_announced(tmp_path):
    src = write_tree(
        tmp_path / "s", {"index.md": "# Home\n\n[next](next.md)\n", "next.md": "# Next\n"}
    )
    proc = _serve(src, tmp_path / "o", "--dev-addr", "127.0.0.1:0")
    seen: list[str] = []
    try:
        base = _address(proc, seen)
        with pytest.raises(urllib.error.HTTPError) as err:
            urllib.request.urlopen(base + "deep/er/missing.html", timeout=10)
        assert err.value.code == 404
        page = err.value.read().decode()
        assert "Page not found" in page and "/__sitegen__/version" in page
        assert "<base href" not in page  # the page sets its own base path over http
        # break a link, then fix it: the fix is announced
        (src / "index.md").write_text("# Home\n\n[next](gone.md)\n", encoding="utf-8")
        _wait_for(proc, r"gone\.md", seen)
        (src / "index.md").write_text("# Home\n\n[next](next.md)\n", encoding="utf-8")
        line = _wait_for(proc, r"fixed:", seen)
        assert "gone.md" in line
    finally:
        proc.terminate()
        proc.wait(timeout=10)


def test_quiet_and_verbose_on_the_site_commands(tmp_path):
    src = write_tree(tmp_path / "s", {"index.md": "# Home\n", "a.md": "# A\n[x](missing.md)\n"})
    quiet = run_cli("build", "-q", "--source", str(src), "--output", str(tmp_path / "o"))
    assert quiet.returncode == 0
    assert "missing.md" in quiet.stderr and "built" not in quiet.stderr  # warnings only
    loud = run_cli("build", "-v", "--source", str(src), "--output", str(tmp_path / "o2"))
    assert "wrote index.html" in loud.stderr and "built" in loud.stderr
    checked = run_cli("check", "-q", str(tmp_path / "o"))  # problems are still printed
    assert checked.returncode == 1 and "missing.md" in checked.stderr
    (src / "a.md").write_text("# A\n", encoding="utf-8")
    run_cli("build", "-q", "--source", str(src), "--output", str(tmp_path / "o"))
    checked = run_cli("check", "-q", str(tmp_path / "o"))
    assert checked.returncode == 0 and checked.stderr == ""
    for command in ("serve", "new", "gh-deploy"):
        helptext = run_cli(command, "--help").stdout
        assert "--quiet" in helptext and "--verbose" in helptext, command
