"""Issue 33: a remote API script and every process it starts reach no socket outside the run:
not a Unix socket of the host, not the host's network by ``setns``, not another process by
``ptrace`` or ``/proc/PID/mem``, not a socket the caller held; and a process the script forks
cannot hand back the run's result (docs/security.md, "Remote API scripts").

Each run goes through a fresh interpreter with its own time limit (test_harden_runner.py's
``_run_script``), so a broken guard fails the test instead of hanging it."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import textwrap

import pytest
from test_harden_runner import _run_script, _script

from sims.remote_api import isolate


def _confined(result: dict) -> None:
    if result["isolation"] != isolate.NAMESPACE:
        if sys.platform.startswith("linux") and os.environ.get("CI"):
            pytest.fail(f"CI is set but the run was not fully confined: {result['isolation']}")
        pytest.skip(f"not fully confined on this machine: {result['isolation']}")


def _probe(code: str) -> str:
    """Script text that runs ``code`` in a separate Python program and prints its last line."""
    return textwrap.dedent(
        f"""
        import subprocess, sys
        done = subprocess.run([sys.executable, "-c", {code!r}], capture_output=True, text=True)
        lines = (done.stdout + done.stderr).strip().splitlines()
        print("PROBE", done.returncode, lines[-1] if lines else "")
        """
    )


def _probe_line(result: dict) -> str:
    return next(x for x in result["stdout"].splitlines() if x.startswith("PROBE"))


def test_no_process_of_the_run_reaches_a_unix_socket_of_the_host(tmp_path):
    path = tmp_path / "host.sock"
    listener = socket.socket(socket.AF_UNIX)
    listener.bind(str(path))
    listener.listen()
    listener.setblocking(False)
    probe = (
        "import socket; s = socket.socket(socket.AF_UNIX); "
        f"s.connect({str(path)!r}); print('connected')"
    )
    try:
        result = _run_script(_script(tmp_path, _probe(probe)))
        with pytest.raises(BlockingIOError):
            listener.accept()
    finally:
        listener.close()
    _confined(result)
    assert _probe_line(result) == "PROBE 1 PermissionError: [Errno 1] Operation not permitted"


def test_root_in_the_run_cannot_enter_the_hosts_network_again(tmp_path):
    """As root, a network namespace alone was left through /proc/PPID/ns/net (setns)."""
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen()
    listener.setblocking(False)
    port = listener.getsockname()[1]
    host_netns = f"/proc/{os.getpid()}/ns/net"  # the test's own: outside the run
    probe = textwrap.dedent(
        f"""
        import ctypes, os, socket
        libc = ctypes.CDLL(None, use_errno=True)
        try:
            fd = os.open({host_netns!r}, os.O_RDONLY)
            entered = libc.setns(fd, 0x40000000) == 0
        except OSError:
            entered = False
        try:
            socket.create_connection(("127.0.0.1", {port}), timeout=3)
            print("entered", entered, "connected")
        except OSError as exc:
            print("entered", entered, "refused", exc.errno)
        """
    )
    try:
        result = _run_script(_script(tmp_path, _probe(probe)))
        with pytest.raises(BlockingIOError):
            listener.accept()
    finally:
        listener.close()
    _confined(result)
    assert _probe_line(result).startswith("PROBE 0 entered False refused")


def test_no_process_of_the_run_can_attach_to_a_process_outside_it(tmp_path):
    target = subprocess.Popen(["sleep", "60"])  # same user, outside the run
    probe = textwrap.dedent(
        f"""
        import ctypes, errno
        libc = ctypes.CDLL(None, use_errno=True)
        traced = libc.ptrace(16, {target.pid}, None, None) == 0  # PTRACE_ATTACH
        try:
            open("/proc/{target.pid}/mem", "r+b").close()
            mem = "opened"
        except OSError as exc:
            mem = errno.errorcode[exc.errno]
        ring = libc.syscall(425, 8, ctypes.create_string_buffer(120))  # io_uring_setup
        print("traced", traced, "mem", mem, "io_uring", ring, errno.errorcode[ctypes.get_errno()])
        """
    )
    try:
        result = _run_script(_script(tmp_path, _probe(probe)))
    finally:
        target.kill()
        target.wait()
    _confined(result)
    assert _probe_line(result) == "PROBE 0 traced False mem EACCES io_uring -1 EPERM"


def test_a_socket_the_caller_held_is_gone_in_the_run(tmp_path):
    """The runner is called from a process holding a connection (a server would); the child
    inherits the descriptor, and finds /dev/null behind it."""
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen()
    port = listener.getsockname()[1]
    script = _script(
        tmp_path,
        """
        import socket, sys
        try:
            socket.socket(fileno=int(sys.argv[1])).send(b"leak")
            print("SENT")
        except OSError as exc:
            print("REFUSED", exc.errno)
        """,
    )
    code = textwrap.dedent(
        f"""
        import socket
        from sims.remote_api.runner import run_script
        held = socket.create_connection(("127.0.0.1", {port}))
        result = run_script({str(script)!r}, "cart", argv=[str(held.fileno())])
        print("ISOLATION", result.isolation)
        held.close()
        """
    )
    from sitegen_helpers import REPO

    try:
        proc = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=120
        )
        conn, _ = listener.accept()
        conn.settimeout(10)
        received = conn.recv(16)
        conn.close()
    finally:
        listener.close()
    isolation = next(x for x in proc.stdout.splitlines() if x.startswith("ISOLATION "))
    _confined({"isolation": isolation[len("ISOLATION ") :]})
    assert received == b"" and "REFUSED 88" in proc.stdout, proc.stdout  # ENOTSOCK


def test_a_process_the_script_forks_cannot_hand_back_the_result(tmp_path):
    script = _script(
        tmp_path,
        """
        import os, sys
        pid = os.fork()
        if pid == 0:
            sys.exit(7)  # the forked copy ends first, through the runner's own code
        os.waitpid(pid, 0)
        print("parent done")
        """,
    )
    result = _run_script(script)
    assert result["exit_code"] == 0 and "parent done" in result["stdout"], result
    assert result["message"] is None


def test_the_guards_leave_the_runs_own_loopback_and_programs_working(tmp_path):
    """What the run provides still works: a server and a client on the run's own loopback
    (brought up inside it, as ``--python`` runs do) and a private socket pair."""
    script = _script(
        tmp_path,
        """
        import fcntl, socket, struct, subprocess, sys
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:  # lo up: SIOCSIFFLAGS
            fcntl.ioctl(s, 0x8914, struct.pack("16sH14s", b"lo", 1, bytes(14)))
        code = (
            "import socket; a, b = socket.socketpair(); a.send(b'pair'); print(b.recv(4));"
            "s = socket.socket(); s.bind(('127.0.0.1', 0)); s.listen();"
            "c = socket.create_connection(s.getsockname()); c.send(b'tcp');"
            "print(s.accept()[0].recv(3))"
        )
        print(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout)
        """,
    )
    result = _run_script(script)
    _confined(result)
    assert "b'pair'\nb'tcp'" in result["stdout"], result


def test_the_isolation_line_names_what_could_not_be_applied(monkeypatch):
    """Where a guard is missing (no libseccomp, no Landlock), the run says so, and the summary
    line shows it (it ends in "only")."""
    from sims.remote_api import confine

    monkeypatch.setattr(confine, "_landlock", lambda libc: False)
    missing = "no seccomp (test): Unix sockets are not fenced"
    monkeypatch.setattr(confine, "_seccomp", lambda: missing)
    outcome = isolate.run_isolated(lambda err: os.getpid(), 60)
    if outcome.isolation == isolate.PROCESS_ONLY:
        pytest.skip("no network namespace on this machine")
    assert outcome.isolation == (
        "own process, own network namespace; no Landlock in this kernel: same-user processes "
        "can be traced; no seccomp (test): Unix sockets are not fenced, for programs it starts "
        "only"
    )
    assert isinstance(outcome.value, int) and outcome.value != os.getpid()
