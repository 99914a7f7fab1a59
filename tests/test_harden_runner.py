"""Issue 15, item 6: the remote API runner runs each script in a child process it can always
end, and the no-network promise holds for every process the script starts (docs/security.md).

Every run here goes through a subprocess with its own time limit: on a runner without these
guarantees the script would hang the test process instead of failing the test."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from sitegen_helpers import REPO


def _script(tmp_path: Path, text: str, name: str = "student.py") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def _cli(*args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "sims.remote_api", *args],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=timeout,
    )


def _run_script(script: Path, limit: float = 120, **kwargs) -> dict:
    """``run_script`` in a fresh interpreter; the RunResult's fields come back as JSON."""
    code = textwrap.dedent(
        f"""
        import json, sys
        from dataclasses import asdict
        from sims.remote_api import runner
        for name, value in {kwargs.pop("patch", {})!r}.items():
            setattr(runner, name, value)
        result = runner.run_script({str(script)!r}, "cart", **{kwargs!r})
        print("RESULT " + json.dumps(asdict(result), default=str))
        """
    )
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=limit
    )
    line = next((x for x in proc.stdout.splitlines() if x.startswith("RESULT ")), None)
    assert line is not None, proc.stderr[-2000:]
    return {**json.loads(line[7:]), "stdout": proc.stdout, "stderr": proc.stderr}


def test_a_thread_that_never_ends_does_not_keep_the_runner_waiting(tmp_path):
    script = _script(
        tmp_path,
        """
        import threading
        threading.Thread(target=threading.Event().wait).start()  # not a daemon: never ends
        print("script done")
        """,
    )
    started = time.monotonic()
    proc = _cli("run", str(script), "--scene", "cart", timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "script done\n" and f"{script.name}: exit 0" in proc.stderr
    assert time.monotonic() - started < 30


def test_a_script_blocked_where_no_exception_reaches_it_is_killed_at_its_limit(tmp_path):
    script = _script(tmp_path, "import threading\nthreading.Event().wait()\n")
    result = _run_script(script, limit=60, patch={"KILL_GRACE": 1.0}, timeout=2.0)
    assert result["exit_code"] == 124 and result["timed_out"]
    assert result["message"] == (
        f"{script}: stopped: the script did not end within its time limit of 2 s (wall-clock "
        "time); its process and every process it started were killed"
    )


def test_processes_a_script_starts_end_with_it(tmp_path):
    pid_file = tmp_path / "pid"
    script = _script(
        tmp_path,
        f"""
        import subprocess
        p = subprocess.Popen(["sleep", "600"])
        open({str(pid_file)!r}, "w").write(str(p.pid))
        """,
    )
    result = _run_script(script)
    assert result["exit_code"] == 0, result["message"]
    pid = int(pid_file.read_text())
    for _ in range(50):  # killed with the child; reaped by init a moment later
        if not _alive(pid):
            break
        time.sleep(0.1)
    assert not _alive(pid)


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def test_a_subprocess_of_the_script_cannot_open_a_connection(tmp_path):
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen()
    listener.setblocking(False)
    port = listener.getsockname()[1]
    script = _script(
        tmp_path,
        f"""
        import subprocess, sys
        probe = "import socket; socket.create_connection(('127.0.0.1', {port}), timeout=5)"
        done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
        print("probe exit", done.returncode, done.stderr.strip().splitlines()[-1:])
        """,
    )
    try:
        result = _run_script(script)
        try:
            listener.accept()
            connected = True
        except BlockingIOError:
            connected = False
    finally:
        listener.close()
    from sims.remote_api import isolate

    if result["isolation"] != isolate.NAMESPACE:
        # without a network namespace the promise is narrower, and the runner says so
        assert result["isolation"] == isolate.PROCESS_ONLY
        pytest.skip(f"no network namespace on this machine: {result['isolation']}")
    assert not connected
    assert "probe exit 1 ['OSError: [Errno 101] Network is unreachable']" in result["stdout"]


def test_the_script_itself_and_its_threads_cannot_connect(tmp_path):
    script = _script(
        tmp_path,
        """
        import socket, threading
        def attempt(where):
            try:
                socket.create_connection(("127.0.0.1", 9), timeout=5)
                print(where, "connected")
            except OSError as exc:
                print(where, "refused:", exc)
        t = threading.Thread(target=attempt, args=("thread",))
        t.start(); t.join()
        attempt("script")
        """,
    )
    result = _run_script(script)
    lines = result["stdout"].splitlines()
    for where in ("thread", "script"):
        line = next(x for x in lines if x.startswith(where))
        assert "refused: socket.connect: network access is disabled" in line, line


def test_negative_zero_or_huge_timeout_is_refused(tmp_path):
    script = _script(tmp_path, "print('ran')\n")
    for value in ("-1", "0", "nan", "1e+308", "inf"):  # 1e308 was an OverflowError traceback
        proc = _cli("run", str(script), "--scene", "cart", "--timeout", value, timeout=60)
        assert proc.returncode == 2 and "ran" not in proc.stdout
        assert (
            f"timeout must be a positive number of seconds, at most 604800 (a week), got {value}"
        ) in proc.stderr
        assert "Traceback" not in proc.stderr


def test_output_exit_codes_and_errors_come_back_from_the_child(tmp_path, capsys):
    from sims.remote_api import isolate
    from sims.remote_api.runner import run_script

    ok = run_script(_script(tmp_path, "print('hello')\nimport sys\nsys.exit(3)\n"), "cart")
    assert ok.exit_code == 3 and capsys.readouterr().out == "hello\n"
    assert ok.isolation in (isolate.NAMESPACE, isolate.PROCESS_ONLY)
    bad = run_script(_script(tmp_path, "x = 1\nraise ValueError('bad')\n", "bad.py"), "cart")
    assert bad.exit_code == 1 and bad.message.endswith("bad.py:2: ValueError: bad")
    gone = run_script(_script(tmp_path, "import os\nos._exit(5)\n", "gone.py"), "cart")
    assert gone.exit_code == 5 and "ended abruptly (status 5)" in gone.message


def test_a_run_inside_the_callers_process_cuts_the_script_off_and_gives_the_network_back(
    tmp_path,
):
    """The clip recorder drives its own World, so its script runs in the recorder's process:
    there, the script's thread gets a network namespace for the run (as root) and the calling
    thread has its network again afterwards."""
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen()
    port = listener.getsockname()[1]
    script = _script(
        tmp_path,
        f"""
        import subprocess, sys
        probe = "import socket; socket.create_connection(('127.0.0.1', {port}), timeout=5)"
        print("probe exit", subprocess.run([sys.executable, "-c", probe]).returncode)
        """,
    )
    code = textwrap.dedent(
        f"""
        import socket
        from sims.remote_api import runner
        result = runner.run_script({str(script)!r}, "cart", isolate=False)
        print("ISOLATION", result.isolation)
        socket.create_connection(("127.0.0.1", {port}), timeout=5).close()
        print("CALLER CONNECTED")
        """
    )
    try:
        proc = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=120
        )
    finally:
        listener.close()
    assert "CALLER CONNECTED" in proc.stdout, proc.stderr[-2000:]
    if os.geteuid() != 0:
        assert "ISOLATION caller's process; sockets refused for the script's thread only" in (
            proc.stdout
        )
        pytest.skip("not root: a thread cannot get a network namespace and come back")
    assert "probe exit 1" in proc.stdout
    assert "ISOLATION caller's process; the script's thread in its own network namespace" in (
        proc.stdout
    )
