"""Run one script in a child process that the runner can always end, with no network.

Why a child process: a script is ordinary Python. It may start a thread that never ends (the
interpreter would wait for it forever after the script's ``exit 0``), block in C code where no
exception reaches it, or start programs of its own. A forked child holds all of that: when the
script is done, or its time is up, the child and everything it started are killed.

Why a network namespace: the in-process socket guard only sees Python sockets of the script's
own process; a program the script starts (``subprocess.run(["curl", ...])``) would not be
stopped by it. The child first moves into a new user and network namespace, which has no
interfaces but a loopback that is down, so no process in its tree can reach any address,
loopback included. The user namespace is made as root too: root outside keeps no capability in
there, so nothing in the run can ``setns`` back into the host's network. Then the child closes
the ways round a network namespace (Unix sockets, ptrace, io_uring, inherited sockets:
confine.py). That needs root or unprivileged user namespaces; where neither is available the
child runs without one and :class:`Outcome` says so (``isolation``), so callers can tell the
user. Only the child itself hands back a result: a process the script forks that returns
through the runner exits without a word.
"""

from __future__ import annotations

import contextlib
import ctypes
import io
import os
import pickle
import signal
import sys
import time
import traceback
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from multiprocessing.connection import Connection, Pipe
from typing import Any, TextIO

CLONE_NEWNET = 0x40000000
CLONE_NEWUSER = 0x10000000
NAMESPACE = (
    "own process, own user and network namespace (no network, no Unix socket, for any "
    "process it starts)"
)
PROCESS_ONLY = (
    "own process; no network namespace available: sockets are refused in that process only"
)
NAMESPACE_ONLY = "own process, own network namespace; {missing}, for programs it starts only"
INTERRUPT_GRACE = 3.0  # seconds a Ctrl-C'd script gets to report where it stopped
PR_SET_PDEATHSIG = 1
_fenced: str | None = None  # in a fenced child: its isolation line
KILL_GRACE = 15.0  # call_isolated's callers give a child this long past its own limit
MAX_WAIT = 86400.0  # one poll() at most (it cannot take a timeout of 1e308 s)


@dataclass
class Outcome:
    """What came back from the child."""

    value: Any = None  # what ``fn`` returned, if it returned
    error: BaseException | None = None  # what ``fn`` raised (not the script: the runner)
    status: int | None = None  # the child's exit status when it ended without a value
    killed: bool = False  # killed at the deadline
    interrupted: bool = False  # Ctrl-C reached the parent
    isolation: str = ""


class _Relay(io.TextIOBase):
    """A text stream in the child whose lines are written by the parent to its own stream."""

    def __init__(self, conn: Connection, kind: str, like: Any):
        self.conn, self.kind, self.pending = conn, kind, ""
        try:
            self.tty = bool(like.isatty())
        except (AttributeError, ValueError, OSError):
            self.tty = False

    def writable(self) -> bool:
        return True

    def isatty(self) -> bool:
        return self.tty

    @property
    def encoding(self) -> str:  # type: ignore[override]
        return "utf-8"

    def write(self, text: str) -> int:
        self.pending += str(text)
        if "\n" in self.pending or len(self.pending) > 8192:
            self.flush()
        return len(text)

    def flush(self) -> None:
        if self.pending:
            text, self.pending = self.pending, ""
            self.conn.send((self.kind, text))


def _is_terminal_stream(stream: Any, fd: int) -> bool:
    """The process's own stream on ``fd`` (writes from a fork land in the same place)."""
    try:
        return (
            stream is not None
            and stream.fileno() == fd
            and stream in (sys.__stdout__, sys.__stderr__)
        )
    except (AttributeError, ValueError, OSError, io.UnsupportedOperation):
        return False


def run_isolated(
    fn: Callable[[TextIO], Any],
    limit: float | None,
    messages: TextIO | None = None,
    cut_network: bool = True,
) -> Outcome:
    """Call ``fn(err)`` in a forked child; ``err`` is where ``fn`` writes its messages (they
    reach ``messages``, else ``sys.stderr``). The script's ``sys.stdout``/``sys.stderr`` reach
    the parent's (relayed through a pipe when those are not the process's real streams, e.g.
    captured by a test). After ``limit`` wall seconds the child and its processes are killed."""
    relay_out = not _is_terminal_stream(sys.stdout, 1)
    relay_err = not _is_terminal_stream(sys.stderr, 2)
    targets = {"out": sys.stdout, "err": sys.stderr, "msg": messages or sys.stderr}
    for stream in targets.values():
        with contextlib.suppress(Exception):
            stream.flush()
    reader, writer = Pipe(duplex=False)
    own_group = not _stdin_is_terminal()
    pid = os.fork()
    if pid == 0:  # pragma: no cover (runs in the child; its outcome is tested from outside)
        reader.close()
        _child(fn, writer, own_group, cut_network, relay_out, relay_err, messages is not None)
    writer.close()
    return _parent(pid, reader, targets, limit, own_group)


def _stdin_is_terminal() -> bool:
    """A child in its own process group may not read the terminal: keep it in ours then."""
    try:
        return os.isatty(0)
    except OSError:
        return False


def _child(
    fn: Callable[[TextIO], Any],
    conn: Connection,
    own_group: bool,
    cut_network: bool,
    relay_out: bool,
    relay_err: bool,
    relay_msg: bool,
) -> None:  # pragma: no cover (runs in the child)
    global _fenced
    status = 0
    me = os.getpid()
    try:
        _die_with_parent()
        if own_group:
            os.setpgid(0, 0)
        netns = None
        if not cut_network:
            isolation = "own process; network allowed by the caller"
        else:
            isolation, own = _fence()
            netns = _netns_id("self") if own else None
            _fenced = isolation
        conn.send(("isolation", (isolation, netns)))
        if relay_out:
            sys.stdout = _Relay(conn, "out", sys.stdout)
        if relay_err:
            sys.stderr = _Relay(conn, "err", sys.stderr)
        err = _Relay(conn, "msg", sys.stderr) if relay_msg else sys.stderr
        try:
            value = fn(err)
            reply: tuple[str, Any] = ("value", value)
        except BaseException as exc:  # noqa: BLE001 (the runner's own failure: hand it over)
            reply = ("error", _picklable(exc))
        for stream in (err, sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        if os.getpid() == me:  # not a process the script forked, come back through here
            conn.send(reply)
    except BaseException:  # noqa: BLE001
        status = 70
        with contextlib.suppress(Exception):
            os.write(2, traceback.format_exc().encode("utf-8", "replace"))
    finally:
        os._exit(status)  # also ends every thread the script started


def _die_with_parent() -> None:
    """The child is killed when the process that forked it ends, however it ends (a killed
    ``sitegen`` or clip worker leaves no run behind)."""
    parent = os.getppid()
    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    if os.getppid() != parent:  # the parent ended before the line above
        os._exit(70)


def fenced() -> str | None:
    """In a child that :func:`run_isolated` fenced: its isolation line; otherwise None."""
    return _fenced


def call_isolated(fn: Callable[[], Any], limit: float | None, what: str) -> Any:
    """``fn()`` in a fenced child (:func:`run_isolated`): its value, or the exception it raised,
    raised here. A child that passes ``limit`` wall seconds is killed (TimeoutError); one that
    ends without an answer is a RuntimeError; both name ``what``."""
    outcome = run_isolated(lambda _err: fn(), limit)
    if outcome.error is not None:
        raise outcome.error
    if outcome.interrupted:
        raise KeyboardInterrupt
    if outcome.killed:
        raise TimeoutError(f"{what} did not end within {limit:g} s: its process was killed")
    if outcome.status is not None:
        raise RuntimeError(f"{what}: its process ended abruptly (status {outcome.status})")
    return outcome.value


def _picklable(exc: BaseException) -> BaseException:
    try:
        pickle.dumps(exc)
        return exc
    except Exception:  # noqa: BLE001
        return RuntimeError("".join(traceback.format_exception(exc)).strip())


def _fence() -> tuple[str, bool]:
    """Namespaces, then confine.py's guards: the isolation line saying what holds, and whether
    the child has a network namespace of its own."""
    from .confine import confine

    own = _new_network_namespace()
    missing = confine() if sys.platform.startswith("linux") else ["not Linux"]
    if not own:
        return PROCESS_ONLY, False
    if own != "user":
        missing.insert(0, "no user namespace: root in the run keeps its rights outside")
    if not missing:
        return NAMESPACE, True
    return NAMESPACE_ONLY.format(missing="; ".join(missing)), True


def _new_network_namespace() -> str | None:
    """Move this (just forked, single-threaded) process into a user and network namespace of
    its own ("user"), or a network namespace only (root where user namespaces are off: "net"),
    or none (None)."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(None, use_errno=True)
    except OSError:
        return None
    uid, gid = os.getuid(), os.getgid()
    if libc.unshare(CLONE_NEWUSER | CLONE_NEWNET) != 0:
        return "net" if libc.unshare(CLONE_NEWNET) == 0 else None
    with contextlib.suppress(OSError):  # keep our own uid/gid inside the user namespace
        for name, text in (
            ("setgroups", "deny"),
            ("uid_map", f"{uid} {uid} 1"),
            ("gid_map", f"{gid} {gid} 1"),
        ):
            with open(f"/proc/self/{name}", "w", encoding="ascii") as fh:
                fh.write(text)
    return "user"


@contextlib.contextmanager
def thread_network_namespace() -> Iterator[bool]:
    """For a run inside the caller's process: this thread, and the threads and processes it
    starts meanwhile, get a network namespace of their own, and the thread returns to its
    own namespace afterwards. Root only (a thread cannot come back out of a user namespace);
    yields whether it took effect."""
    if _fenced is not None:  # this whole process is fenced already (and cannot come back)
        yield _fenced != PROCESS_ONLY
        return
    fd = -1
    with contextlib.suppress(OSError):
        if sys.platform.startswith("linux") and os.geteuid() == 0:
            fd = os.open("/proc/thread-self/ns/net", os.O_RDONLY | os.O_CLOEXEC)
    if fd < 0:
        yield False
        return
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.unshare(CLONE_NEWNET) != 0:
            yield False
            return
        try:
            yield True
        finally:
            if libc.setns(fd, CLONE_NEWNET) != 0:
                err = ctypes.get_errno()
                raise OSError(err, f"cannot return to the network namespace: {os.strerror(err)}")
    finally:
        os.close(fd)


def _netns_id(pid: str) -> str | None:
    try:
        return os.readlink(f"/proc/{pid}/ns/net")
    except OSError:
        return None


def _parent(
    pid: int, conn: Connection, targets: dict[str, Any], limit: float | None, own_group: bool
) -> Outcome:
    outcome = Outcome()
    netns: str | None = None
    deadline = None if limit is None else time.monotonic() + limit
    got_reply = False
    try:
        while True:
            wait = None if deadline is None else max(0.0, deadline - time.monotonic())
            try:
                if not conn.poll(None if wait is None else min(wait, MAX_WAIT)):
                    if wait is not None and wait > MAX_WAIT:
                        continue  # a long limit, waited for in steps poll() can take
                    outcome.killed = not outcome.interrupted
                    break
                kind, payload = conn.recv()
            except KeyboardInterrupt:
                outcome.interrupted = True
                if own_group:  # a Ctrl-C from the terminal did not reach the child
                    with contextlib.suppress(OSError):
                        os.kill(pid, signal.SIGINT)
                deadline = time.monotonic() + INTERRUPT_GRACE
                continue
            except Exception:  # noqa: BLE001 (the end, or bytes garbled by a forked process)
                break
            if kind == "isolation":
                outcome.isolation, netns = payload
            elif kind in ("out", "err", "msg"):
                with contextlib.suppress(Exception):
                    targets[kind].write(payload)
                    targets[kind].flush()
            elif kind == "value":
                outcome.value, got_reply = payload, True
                break
            elif kind == "error":
                outcome.error, got_reply = payload, True
                break
    finally:
        _end_tree(pid, netns, own_group)
        conn.close()
        _, status = os.waitpid(pid, 0)
    if not got_reply and not outcome.killed:
        outcome.status = os.waitstatus_to_exitcode(status)
    return outcome


def _end_tree(pid: int, netns: str | None, own_group: bool) -> None:
    """Kill the child and every process it started (before reaping it, so no pid is reused):
    its descendants, its process group, and anything else inside its network namespace."""
    victims = {pid} | _descendants(pid)
    if netns is not None:
        victims |= {p for p in _all_pids() if _netns_id(str(p)) == netns}
    victims.discard(os.getpid())
    for victim in victims:
        with contextlib.suppress(OSError):
            os.kill(victim, signal.SIGKILL)
    if own_group:
        with contextlib.suppress(OSError):
            os.killpg(pid, signal.SIGKILL)


def _all_pids() -> list[int]:
    try:
        return [int(name) for name in os.listdir("/proc") if name.isdigit()]
    except OSError:
        return []


def _descendants(root: int) -> set[int]:
    """Processes below ``root``, from each process's parent in ``/proc/N/stat``."""
    children: dict[int, list[int]] = {}
    for p in _all_pids():
        try:
            with open(f"/proc/{p}/stat", "rb") as fh:
                stat = fh.read()
        except OSError:
            continue
        fields = stat[stat.rfind(b")") + 2 :].split()
        if len(fields) > 1:
            children.setdefault(int(fields[1]), []).append(p)
    found: set[int] = set()
    stack = [root]
    while stack:
        for child in children.get(stack.pop(), []):
            if child not in found:
                found.add(child)
                stack.append(child)
    return found
