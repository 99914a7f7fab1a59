"""What keeps a remote API run's process tree from reaching anything outside it (isolate.py).

A network namespace stops IP, but not everything a process can talk to: a Unix socket of the
host (``/run/...``, ``/tmp/.X11-unix``, a user's agent socket) is reached through the file
system; a root process can ``setns`` back into the host's network through ``/proc/PID/ns/net``;
a process of the same user can be attached (``ptrace``, ``/proc/PID/mem``) and made to connect
for it; ``io_uring`` makes sockets without the ``socket`` system call. Once in its own user and
network namespace (isolate.py), the child closes those doors for itself and everything it
starts, programs in other languages included (both guards are inherited across ``exec``):

- a seccomp filter (``pyseccomp``, the ctypes binding of libseccomp): ``socket()`` only for
  ``AF_INET``/``AF_INET6`` (the run's own namespace: nothing but its loopback) and
  ``AF_NETLINK`` with ``NETLINK_ROUTE`` (the namespace's own interfaces); ``socketpair()``
  stays (a private pair); ``io_uring_*``, ``ptrace``, ``process_vm_*``, ``pidfd_getfd`` and
  ``setns`` fail with EPERM. Arguments are compared on their low 32 bits, as the kernel reads
  them. A 32-bit system call on a 64-bit machine is not in the filter's architecture and kills
  the process (libseccomp's default), so it is no way round.
- a Landlock domain, where the kernel has Landlock (``/sys/kernel/security/landlock``; ABI 1 and
  later): no process of the run can trace or read the memory of a process outside it; from
  ABI 6 on also no signal to one, and no abstract Unix socket outside.
- socket descriptors inherited from the caller (a server's listening socket, say) are replaced
  by ``/dev/null`` (the standard streams are kept as given).

Why Landlock by hand (three system calls through ctypes): the PyPI binding ``landlock``
(1.0.0.dev5) is a pre-release and knows only file-system rules, not the scopes used here.

:func:`confine` returns what it could not apply (empty: everything held), for the isolation line.
"""

from __future__ import annotations

import ctypes
import errno
import os
import socket
import stat

NETLINK_ROUTE = 0
LOW32 = 0xFFFFFFFF
ALLOWED_FAMILIES = (socket.AF_INET, socket.AF_INET6, socket.AF_NETLINK)
DENIED_CALLS = (
    "io_uring_setup",
    "io_uring_enter",
    "io_uring_register",
    "ptrace",
    "process_vm_readv",
    "process_vm_writev",
    "pidfd_getfd",
    "setns",
)
# Landlock (include/uapi/linux/landlock.h): the same numbers on every architecture
SYS_LANDLOCK_CREATE_RULESET, SYS_LANDLOCK_RESTRICT_SELF = 444, 446
LANDLOCK_CREATE_RULESET_VERSION = 1
LANDLOCK_ACCESS_FS_MAKE_CHAR, LANDLOCK_ACCESS_FS_MAKE_BLOCK = 1 << 6, 1 << 11
LANDLOCK_SCOPE_ABSTRACT_UNIX_SOCKET, LANDLOCK_SCOPE_SIGNAL = 1 << 0, 1 << 1
PR_SET_NO_NEW_PRIVS = 38


def confine() -> list[str]:
    """Apply every guard above to this (single-threaded, just forked) process; return what
    could not be applied, each as a few words for the isolation line."""
    missing: list[str] = []
    _drop_inherited_sockets()
    libc = ctypes.CDLL(None, use_errno=True)
    if libc.prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0:
        missing.append("no_new_privs refused")
    if not _landlock(libc):
        missing.append("no Landlock in this kernel: same-user processes can be traced")
    problem = _seccomp()
    if problem:
        missing.append(problem)
    return missing


def _drop_inherited_sockets() -> None:
    """Every socket descriptor above the standard streams becomes ``/dev/null``: the numbers
    stay valid for whatever holds them, the connections are gone."""
    try:
        fds = [int(name) for name in os.listdir("/proc/self/fd")]
    except OSError:
        return
    null = -1
    for fd in fds:
        if fd <= 2:
            continue
        try:
            if not stat.S_ISSOCK(os.fstat(fd).st_mode):
                continue
            if null < 0:
                null = os.open(os.devnull, os.O_RDWR | os.O_CLOEXEC)
            os.dup2(null, fd, inheritable=os.get_inheritable(fd))
        except OSError:
            continue
    if null >= 0:
        os.close(null)


def _seccomp() -> str | None:
    """Load the filter; None when it is in force, else why not."""
    try:
        import pyseccomp as sc
    except (ImportError, OSError, AttributeError):
        return "no seccomp (pyseccomp or libseccomp missing): Unix sockets are not fenced"
    try:
        f = sc.SyscallFilter(sc.ALLOW)
        deny = sc.ERRNO(errno.EPERM)
        for family in range(64):
            if family not in ALLOWED_FAMILIES:
                f.add_rule(deny, "socket", sc.Arg(0, sc.MASKED_EQ, LOW32, family))
        for bit in range(6, 32):  # any family of 64 or more
            f.add_rule(deny, "socket", sc.Arg(0, sc.MASKED_EQ, 1 << bit, 1 << bit))
        for bit in range(32):  # netlink: the route family only (protocol 0)
            f.add_rule(
                deny,
                "socket",
                sc.Arg(0, sc.MASKED_EQ, LOW32, socket.AF_NETLINK),
                sc.Arg(2, sc.MASKED_EQ, 1 << bit, 1 << bit),
            )
        for name in DENIED_CALLS:
            try:
                f.add_rule(deny, name)
            except (OSError, ValueError):  # a call this architecture does not have
                continue
        f.load()
    except (OSError, ValueError) as exc:
        return f"no seccomp ({exc}): Unix sockets are not fenced"
    return None


class _RulesetAttr(ctypes.Structure):
    _fields_ = [
        ("handled_access_fs", ctypes.c_uint64),
        ("handled_access_net", ctypes.c_uint64),
        ("scoped", ctypes.c_uint64),
    ]


def _landlock(libc: ctypes.CDLL) -> bool:
    """Enter a Landlock domain that allows every file access but making device nodes (a
    domain needs some rule); its ptrace restriction, and from ABI 6 its scopes, are the
    point. False where the kernel has no Landlock."""
    libc.syscall.restype = ctypes.c_long
    abi = libc.syscall(SYS_LANDLOCK_CREATE_RULESET, None, ctypes.c_size_t(0),
                       ctypes.c_uint32(LANDLOCK_CREATE_RULESET_VERSION))  # fmt: skip
    if abi < 1:
        return False
    attr = _RulesetAttr(LANDLOCK_ACCESS_FS_MAKE_CHAR | LANDLOCK_ACCESS_FS_MAKE_BLOCK, 0, 0)
    size = 8  # ABI 1-3: handled_access_fs only
    if abi >= 6:
        attr.scoped = LANDLOCK_SCOPE_ABSTRACT_UNIX_SOCKET | LANDLOCK_SCOPE_SIGNAL
        size = ctypes.sizeof(_RulesetAttr)
    elif abi >= 4:
        size = 16
    fd = libc.syscall(SYS_LANDLOCK_CREATE_RULESET, ctypes.byref(attr), ctypes.c_size_t(size),
                      ctypes.c_uint32(0))  # fmt: skip
    if fd < 0:
        return False
    try:
        return libc.syscall(SYS_LANDLOCK_RESTRICT_SELF, ctypes.c_int(fd), ctypes.c_uint32(0)) == 0
    finally:
        os.close(fd)
