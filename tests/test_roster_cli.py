"""CLI: exit codes (0 ok, 1 errors, 2 usage), one-line diagnostics, never a traceback."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from roster.cli import main

FIXTURES = Path(__file__).parent / "fixtures" / "roster"
REAL = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "stage3_2a.txt"
DIAG_LINE = re.compile(r"^\S.*?(:\d+)?: (error|warning|info): [^:]+: .+$")


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return code, out, err


@pytest.fixture
def good(tmp_path: Path) -> Path:
    path = tmp_path / "good.txt"
    path.write_text(
        "g_1\t40823101\t40823101\t40823112\ta40823112\ng_2\t40823102\t40823102\n", encoding="utf-8"
    )
    (tmp_path / "good.corrections.yml").write_text(
        'aliases: {"40823112": a40823112}\ngroup_names: [{replace: "_", with: "-"}]\n',
        encoding="utf-8",
    )
    return path


@pytest.fixture
def bad(tmp_path: Path) -> Path:
    path = tmp_path / "bad.txt"
    path.write_text("g\t40823101\tjavascript:alert(1)\nh\thello\t40823102\n", encoding="utf-8")
    return path


def test_check_ok_prints_groups_members_and_corrections(capsys, good: Path) -> None:
    code, out, _ = run(capsys, "check", str(good))
    assert code == 0
    assert f"roster: {good} (tsv, paired layout): 2 groups, 3 members" in out
    assert "g-1  (slug g-1, leader 40823101, 2 members, line 1)" in out
    assert "  40823112  a40823112" in out
    assert "corrections applied (3):" in out
    assert out.rstrip().endswith("OK: 0 errors, 0 warnings")


def test_check_with_errors_exits_1_with_one_line_each(capsys, bad: Path) -> None:
    code, out, _ = run(capsys, "check", str(bad))
    assert code == 1
    errors = out.split("errors (3):\n")[1].splitlines()[:3]
    assert all(DIAG_LINE.match(line.strip()) for line in errors)
    assert f"  {bad}:1: error: member 1 account (col 3): account 'javascript:alert(1)'" in out
    assert f"  {bad}:2: error: member 1 id (col 2): 'hello' is not a student id" in out


def test_links_html_json_csv(capsys, good: Path) -> None:
    code, out, err = run(capsys, "links", str(good))
    assert code == 0 and err == ""
    assert '<a href="https://github.com/40823101/g-1">g-1 repo</a>' in out
    code, out, _ = run(capsys, "links", str(good), "--format", "json", "--course-repo", "cd2022")
    assert code == 0
    assert (
        json.loads(out)["groups"][0]["members"][1]["site_url"]
        == "https://a40823112.github.io/cd2022"
    )
    code, out, _ = run(capsys, "links", str(good), "--format", "csv", "--no-corrections")
    assert out.splitlines()[1].startswith("g_1,40823101,40823101,yes,")


def test_links_with_errors_prints_no_links_and_exits_1(capsys, bad: Path) -> None:
    code, out, err = run(capsys, "links", str(bad))
    assert code == 1
    assert out == ""
    assert "no links printed" in err
    assert all(DIAG_LINE.match(line) for line in err.splitlines()[:-1])


def test_warnings_go_to_stderr_and_do_not_fail(capsys, tmp_path: Path) -> None:
    path = tmp_path / "w.txt"
    path.write_text("g\t40823101*\t40823101\n", encoding="utf-8")
    code, out, err = run(capsys, "links", str(path))
    assert code == 0 and "annotation '*'" in err and "<section" in out


@pytest.mark.parametrize(
    "argv",
    [
        [],
        ["nonsense"],
        ["check"],
        ["links", "x.txt", "--format", "pdf"],
        ["check", "x.txt", "--corrections", "a.yml", "--no-corrections"],
    ],
)
def test_usage_errors_exit_2(capsys, argv: list[str]) -> None:
    code, _, err = run(capsys, *argv)
    assert code == 2
    assert "usage: sitegen roster" in err


def test_help_exits_0(capsys) -> None:
    code, out, _ = run(capsys, "--help")
    assert code == 0 and "check" in out and "links" in out


@pytest.mark.parametrize(
    "name, content, message",
    [
        ("missing.txt", None, "no such file"),
        ("roster.xlsx", b"PK", "unsupported roster file type"),
        ("dir.txt", "DIR", "is a directory"),
    ],
)
def test_unreadable_files_are_one_line_exit_1(
    capsys, tmp_path: Path, name, content, message
) -> None:
    path = tmp_path / name
    if content == "DIR":
        path.mkdir()
    elif content is not None:
        path.write_bytes(content)
    code, out, err = run(capsys, "check", str(path))
    assert code == 1
    assert err.count("\n") == 1 and message in err and DIAG_LINE.match(err.strip())


def test_missing_corrections_file_is_one_line(capsys, good: Path) -> None:
    code, _, err = run(capsys, "check", str(good), "--corrections", str(good.parent / "nope.yml"))
    assert code == 1 and err.strip().endswith("nope.yml: error: file: no such file")


def test_diff_subcommand(capsys, good: Path, tmp_path: Path) -> None:
    code, old_json, _ = run(capsys, "links", str(good), "--format", "json", "--no-corrections")
    snapshot = tmp_path / "old.json"
    snapshot.write_text(old_json, encoding="utf-8")
    code, out, _ = run(capsys, "diff", str(snapshot), str(good))
    assert code == 0
    assert out.splitlines() == [
        "group renamed: g_1 -> g-1",
        "group renamed: g_2 -> g-2",
    ]
    code, out, _ = run(capsys, "diff", str(good), str(good))
    assert (code, out) == (0, "no changes\n")
    (tmp_path / "junk.json").write_text("[1]", encoding="utf-8")
    code, _, err = run(capsys, "diff", str(tmp_path / "junk.json"), str(good))
    assert code == 1 and "not roster JSON" in err


def test_python_dash_m_roster(tmp_path: Path) -> None:
    root = Path(__file__).resolve().parents[1]
    done = subprocess.run(
        [sys.executable, "-m", "roster", "links", str(FIXTURES / "small.csv"), "--format", "json"],
        cwd=root,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 0, done.stderr
    assert len(json.loads(done.stdout)["groups"]) == 2
    done = subprocess.run(
        [sys.executable, "-m", "roster", "check", str(tmp_path / "none.txt")],
        cwd=root,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert done.stderr.strip() == f"{tmp_path / 'none.txt'}: error: file: no such file"
    done = subprocess.run(
        [sys.executable, "-m", "roster"], cwd=root, capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 2 and "usage: python -m roster" in done.stderr


@pytest.mark.needs_shared("data", "stage3_2a.txt")
def test_real_roster_check_is_ok(capsys) -> None:
    code, out, _ = run(
        capsys, "check", str(REAL), "--corrections", str(FIXTURES / "stage3_2a.corrections.yml")
    )
    assert code == 0
    assert "6 groups, 46 members" in out
    # 40623121 (an earlier cohort) is one digit from 40823121: said, with both lines
    # the two earlier-cohort ids are one warning naming both (issue 30: one line per kind)
    assert "warnings (3):" in out
    assert "2 ids look unlike the others (most ids are 8 characters and start with '408')" in out
    assert "id 40623121 is one digit away from 40823121 (line 4" in out
