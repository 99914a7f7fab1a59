"""Issue 33, scene scripts: the instruction budget cannot be escaped (coroutines, pcall,
message handlers, the runner's own functions, finalizers, pattern backtracking); memory is
limited per run; the temporary folder has a quota and stale ones are removed; ``python -m
sims.lua run`` has a wall-clock limit (docs/security.md, "Scene scripts")."""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest
from sitegen_helpers import REPO
from test_lua_runtime import _run, child

from sims.lua import runtime
from sims.lua.host import ScriptHost

STOPPED = "stopped: ran 50 virtual steps' worth of Lua instructions"


@pytest.mark.parametrize(
    "body",
    [
        # a coroutine the script makes: a hook belongs to one coroutine
        "local co = coroutine.create(function() while true do end end)\n  coroutine.resume(co)",
        "coroutine.wrap(function() while true do end end)()",
        # catching the budget's error and going on
        "while true do pcall(function() while true do end end) end",
        # a message handler that never returns
        "xpcall(function() error('x') end, function() while true do end end)",
    ],
    ids=["coroutine", "wrap", "pcall", "xpcall-handler"],
)
def test_an_endless_loop_is_stopped_wherever_it_hides(body):
    started = time.monotonic()
    host = _run(
        child(f"function sysCall_init()\n  {body}\nend\n"),
        child("function sysCall_sensing() sim.setIntegerSignal('alive', 1) end", on=6),
        seconds=0.2,
    )
    assert len(host.errors) == 1 and STOPPED in host.errors[0], host.errors
    assert host.signals["int"]["alive"] == 1  # the other script and the run went on
    assert time.monotonic() - started < 60


def test_the_runners_own_functions_are_out_of_reach():
    host = _run(
        child(
            "function sysCall_init()\n"
            "  local found, level = 0, 1\n"
            "  while true do\n"
            "    local info = debug.getinfo(level, 'fSl')\n"
            "    if not info then break end\n"
            "    if info.func ~= nil or info.source == '=prelude' then found = found + 1 end\n"
            "    level = level + 1\n"
            "  end\n"
            "  sim.setIntegerSignal('found', found)\n"
            "  sim.setIntegerSignal('levels', level)\n"
            "  sim.setStringSignal('here', debug.getinfo(1, 'l').currentline .. '')\n"
            "end\n"
        )
    )
    assert host.errors == []
    assert host.signals["int"]["found"] == 0 and host.signals["int"]["levels"] >= 2
    assert host.signals["string"]["here"] == b"11"  # levels still count from the caller


def test_a_finalizer_is_not_run_and_is_reported():
    host = _run(
        child(
            "function sysCall_init()\n"
            "  setmetatable({}, {__gc = function() while true do end end})\n"
            "  for i = 1, 200000 do local t = {i} end\n"
            "  sim.setIntegerSignal('done', 1)\n"
            "end\n"
        ),
        seconds=0.2,
    )
    assert host.errors == [] and host.signals["int"]["done"] == 1
    assert [m.function for m in host.missing] == ["__gc finalizer (not run in scene scripts)"]


def test_pattern_backtracking_past_the_bound_is_refused_and_ordinary_patterns_work():
    host = _run(
        child(
            "function sysCall_init()\n"
            "  local s = string.rep(' word', 400) .. '  '\n"
            "  sim.setStringSignal('trim', (s:match('^%s*(.-)%s*$')):sub(1, 9))\n"
            "  local n = 0\n"
            "  for w in s:gmatch('%a+') do n = n + 1 end\n"
            "  sim.setIntegerSignal('words', n)\n"
            "  string.find(string.rep('a', 3000), '.-.-.-.-.-.-b')\n"
            "end\n"
        )
    )
    assert host.signals["string"]["trim"] == b"word word" and host.signals["int"]["words"] == 400
    assert len(host.errors) == 1
    assert 'Arm:7: string.find: pattern ".-.-.-.-.-.-b" on 3000 characters' in host.errors[0]


def test_memory_is_limited_for_the_whole_run(monkeypatch):
    """Four scripts of 10 MB each under a run limit of 32 MiB: the fourth fails (with a limit
    per script, 16 scripts of a scene reached 3.7 GB)."""
    monkeypatch.setattr(runtime, "MAX_MEMORY", 32 << 20)
    scripts = [
        child(f"function sysCall_init() big{i} = string.rep('x', 10 * 1024 * 1024) end", on=h)
        for i, h in enumerate((4, 5, 6, 7))
    ]
    host = _run(*scripts, seconds=0.1)
    assert len(host.errors) == 1 and "not enough memory" in host.errors[0], host.errors


def test_the_temporary_folder_has_a_quota(monkeypatch):
    monkeypatch.setattr(runtime, "MAX_DISK", 1 << 20)
    host = _run(
        child(
            "function sysCall_init()\n"
            "  local f = io.open(os.tmpname(), 'w')\n"
            "  local chunk = string.rep('x', 300 * 1024)\n"
            "  local ok, err, n = true, nil, 0\n"
            "  while ok do ok, err = f:write(chunk); if ok then n = n + 1 end end\n"
            "  f:close()\n"
            "  sim.setIntegerSignal('chunks', n)\n"
            "  sim.setStringSignal('why', err)\n"
            "end\n"
        ),
        seconds=0.1,
    )
    assert host.errors == [] and host.signals["int"]["chunks"] == 3
    assert host.signals["string"]["why"] == b"sandbox: the run's temporary folder is full (quota)"


def test_temporary_folders_of_dead_runs_are_removed_and_a_run_removes_its_own():
    root = Path(tempfile.gettempdir())
    dead = subprocess.Popen(["true"])
    dead.wait()
    stale = root / f"{runtime.TMP_PREFIX}{dead.pid}-x1"  # a run killed before its cleanup
    stale.mkdir()
    (stale / "data").write_bytes(b"left behind")
    old = root / f"{runtime.TMP_PREFIX}legacyx1"  # an older version's, a day old
    old.mkdir()
    os.utime(old, (time.time() - 2 * 86400,) * 2)
    alive = root / f"{runtime.TMP_PREFIX}{os.getpid()}-x2"  # a live run's
    alive.mkdir()
    try:
        host = _run(child("function sysCall_init() end"), seconds=0.05)
        own = Path(host._tmp.name)
        assert own.name.startswith(f"{runtime.TMP_PREFIX}{os.getpid()}-") and own.is_dir()
        assert not stale.exists() and not old.exists() and alive.exists()
        host.close()
        assert not own.exists()
    finally:
        alive.rmdir()
    assert isinstance(host, ScriptHost)


def test_python_m_sims_lua_run_has_a_wall_clock_limit(tmp_path):
    """Backtracking under the bound still takes long; the command stops at --timeout."""
    scene = tmp_path / "slow.simscene.xml"
    script = "function sysCall_init() string.find(string.rep('a', 90000), '.-b') end"
    scene.write_text(
        "<CoppeliaSim><filetype>simpleScene</filetype><dummy><common><name>d</name></common>"
        f"<childScript><scriptText>{script}</scriptText></childScript></dummy></CoppeliaSim>",
        encoding="utf-8",
    )
    started = time.monotonic()
    proc = subprocess.run(
        [sys.executable, "-m", "sims.lua", "run", str(scene), "--seconds", "0.2", "--timeout", "3"],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=120,
    )
    assert proc.returncode == 124 and "Traceback" not in proc.stderr
    assert proc.stderr.splitlines()[-1] == (
        "error: stopped: the run did not end within its wall-clock limit of 3 s (--timeout); "
        "its process and every process it started were killed"
    )
    assert time.monotonic() - started < 60
    bad = subprocess.run(
        [sys.executable, "-m", "sims.lua", "run", str(scene), "--timeout", "1e308"],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=60,
    )
    assert bad.returncode == 2 and bad.stderr.strip().splitlines()[-1] == (
        "error: --timeout must be a positive number of seconds, at most 604800 (a week), got 1e308"
    )
