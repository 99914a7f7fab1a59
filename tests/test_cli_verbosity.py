"""`-q`/`-v` on every sitegen command (issue 17): each subcommand's help lists both, -q keeps
the command's data and errors but drops informational lines, -v adds detail."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
LUA_SCENE = REPO / "data" / "scenes" / "lua_arm.simscene.xml"

SUBCOMMANDS = [
    ["build"],
    ["serve"],
    ["check"],
    ["new"],
    ["gh-deploy"],
    ["roster", "check"],
    ["roster", "links"],
    ["roster", "diff"],
    ["sims", "list"],
    ["sims", "render"],
    ["remote-api", "run"],
    ["remote-api", "functions"],
    ["import", "cmsimde"],
    ["scene", "show"],
    ["scene", "xml"],
]


def sitegen(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "sitegen", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=300,
    )


def _inputs(work: Path) -> None:
    """The same tiny inputs in each run's own folder (an import writes beside its DEST)."""
    work.mkdir()
    (work / "r.txt").write_text("g_1\t40823101\t40823101\t40823112\ng_2\t40823102\n")
    (work / "r2.txt").write_text("g_1\t40823101\t40823101\ng_2\t40823102\t40823102\n")
    (work / "s.py").write_text('import sim\nsim.simxFinish(-1)\nprint("hello")\n')
    (work / "content.htm").write_text("<h1>A</h1><p>x</p><h2>B</h2><p>y</p>")


# (arguments, whether -v must print more than -q: False where all output is the data)
CASES = {
    "roster-check": (["roster", "check", "--no-corrections", "r.txt"], True),
    "roster-links": (["roster", "links", "--no-corrections", "--format", "json", "r.txt"], True),
    "roster-diff": (["roster", "diff", "r.txt", "r2.txt"], True),
    "sims-list": (["sims", "list"], True),
    "remote-api-run": (["remote-api", "run", "s.py", "--scene", "cart"], True),
    "remote-api-functions": (["remote-api", "functions"], False),
    "import": (["import", "cmsimde", "content.htm", "--dest", "content"], True),
    "scene-show": (["scene", "show", str(LUA_SCENE)], False),
    "scene-xml": (["scene", "xml", str(LUA_SCENE), "-o", "out.xml"], True),
}


def _lines(proc: subprocess.CompletedProcess) -> list[str]:
    # pybullet's C library prints its build date itself; it is not sitegen's to silence
    text = proc.stdout + proc.stderr
    return [ln.strip() for ln in text.splitlines() if ln.strip() and "pybullet build" not in ln]


@pytest.mark.parametrize("case", sorted(CASES))
def test_quiet_prints_a_subset_of_verbose(tmp_path: Path, case: str) -> None:
    args, verbose_says_more = CASES[case]
    runs = {}
    for flag in ("-q", "-v"):
        work = tmp_path / flag.strip("-")
        _inputs(work)
        runs[flag] = proc = sitegen(*args, flag, cwd=work)
        assert proc.returncode == 0, (flag, proc.stderr)
        assert "Traceback" not in proc.stderr
    quiet, verbose = _lines(runs["-q"]), _lines(runs["-v"])
    whole = "\n".join(verbose)
    assert all(line in whole for line in quiet), (quiet, verbose)
    if verbose_says_more:
        assert len(quiet) < len(verbose), (quiet, verbose)
    else:
        assert runs["-q"].stdout == runs["-v"].stdout  # the data itself is never dropped
    if case == "roster-links":  # the links are the data: identical either way
        assert runs["-q"].stdout == runs["-v"].stdout and '"groups"' in runs["-q"].stdout
    if case == "scene-xml":
        assert (tmp_path / "q" / "out.xml").read_text() == (tmp_path / "v" / "out.xml").read_text()


def test_quiet_still_prints_errors(tmp_path: Path) -> None:
    (tmp_path / "bad.txt").write_text("g_1\t40823101\tnot an id\n")
    checked = sitegen("roster", "check", "--no-corrections", "-q", "bad.txt", cwd=tmp_path)
    assert checked.returncode == 1 and "error" in checked.stdout
    missing = sitegen("scene", "show", "-q", "nope.ttt", cwd=tmp_path)
    assert missing.returncode == 1 and "nope.ttt" in missing.stderr


@pytest.mark.parametrize("command", SUBCOMMANDS, ids=" ".join)
def test_every_subcommand_help_lists_quiet_and_verbose(tmp_path: Path, command: list[str]) -> None:
    helped = sitegen(*command, "--help", cwd=tmp_path)
    assert helped.returncode == 0, helped.stderr
    for option in ("-q", "--quiet", "-v", "--verbose"):
        assert option in helped.stdout, (command, option)
