"""How a remote API call travels: operation modes, reply buffers and return codes.

``execute`` is the client library's ``_exec`` (extApi.c) and the server's reply in one:

- blocking (``oneshot_wait``): run the command now (waiting for the server's next simulation
  pass when a simulation runs) and return its reply; the reply is not kept in the buffer.
- oneshot: run the command, keep its reply, return the *previous* reply to the same command if
  there is one, else novalue (so a setter's first oneshot call returns 1).
- streaming: like oneshot the first time (novalue, zeroed outputs); from then on the server keeps
  the reply current, and streaming/buffer calls return the latest value.
- buffer: send nothing; return the kept reply (a stream's is kept current), else novalue.
- discontinue: run once more, stop the stream, return the kept reply.
- remove: drop the kept reply: ok if there was one, novalue if not.
- split modes behave as their plain counterparts; an unknown mode is illegal (flag 4).

Outputs are zeroed whenever the code is not 0, as ``sim.py`` leaves them.
"""

from __future__ import annotations

import ctypes
import numbers
import operator
from collections.abc import Callable
from typing import Any

from . import constants as C
from .client import Client, Reply, Session, current_session
from .commands import CommandError

OK = C.simx_return_ok
NOVALUE = C.simx_return_novalue_flag
ILLEGAL = C.simx_return_illegal_opmode_flag
REMOTE = C.simx_return_remote_error_flag
LOCAL = C.simx_return_local_error_flag
INIT = C.simx_return_initialize_error_flag

ONESHOT, BLOCKING, STREAMING = (
    C.simx_opmode_oneshot,
    C.simx_opmode_blocking,
    C.simx_opmode_streaming,
)
BUFFER, DISCONTINUE, REMOVE = C.simx_opmode_buffer, C.simx_opmode_discontinue, C.simx_opmode_remove
_CANONICAL = {
    C.simx_opmode_oneshot_split: ONESHOT,
    C.simx_opmode_streaming_split: STREAMING,
}

Run = Callable[[Any], tuple]


# --- argument checks (ctypes raises ArgumentError for these in the real sim.py) ------------------
def int_arg(value: Any, position: int) -> int:
    """What ctypes' c_int takes: an int, or an object with ``__index__`` (numpy's integers)."""
    if isinstance(value, numbers.Integral):
        return int(value)
    if not isinstance(value, (float, str, bytes)) and hasattr(type(value), "__index__"):
        try:
            return operator.index(value)
        except TypeError:
            pass
    raise ctypes.ArgumentError(f"argument {position}: TypeError: wrong type")


def float_arg(value: Any, position: int) -> float:
    """What ctypes' c_float takes: a number, or an object with ``__float__`` (a numpy scalar,
    or a numpy array holding one value, as course scripts pass ``theta[0]``)."""
    if isinstance(value, numbers.Real):
        return float(value)
    if not isinstance(value, (str, bytes)) and hasattr(type(value), "__float__"):
        try:
            if getattr(value, "size", None) == 1 and hasattr(value, "item"):
                return float(value.item())  # what numpy < 2's __float__ did for any 1-value array
            return float(value)
        except (TypeError, ValueError):
            pass
    raise ctypes.ArgumentError(f"argument {position}: TypeError: wrong type")


def str_arg(value: Any, position: int) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, (bytes, bytearray)):
        return bytes(value).decode("utf-8", "replace")
    raise ctypes.ArgumentError(f"argument {position}: TypeError: wrong type")


def f32(x: float) -> float:
    """A value as it arrives through the C API (32-bit float)."""
    return ctypes.c_float(float(x)).value


def f32s(values) -> list[float]:
    return [f32(v) for v in values]


def mode_of(opmode: Any) -> int | None:
    if not isinstance(opmode, numbers.Integral) or int(opmode) < 0:
        return None
    base = int(opmode) & 0xFFFF0000
    base = _CANONICAL.get(base, base)
    return base if base in C.OPMODE_BASES else None


# --- the call ----------------------------------------------------------------------------------
def lookup(client_id: Any) -> tuple[Session, Client] | None:
    session = current_session()
    if session is None or session.simulator is None:
        return None
    client = session.client(client_id)
    return None if client is None else (session, client)


def run_command(session: Session, run: Run, zero: tuple) -> Reply:
    sim = session.simulator
    try:
        values = run(sim.world)
        code = OK
    except CommandError as exc:
        values, code = zero, REMOTE
        sim.errors.append(str(exc))
        del sim.errors[:-50]
    return Reply(code, tuple(values), sim.sim_time)


def fetch(client: Client, reply: Reply | None, zero: tuple) -> tuple[int, tuple]:
    if reply is None:
        return NOVALUE, zero
    client.last_cmd_time = reply.sim_time
    return reply.code, (reply.values if reply.code == OK else zero)


def execute(
    client_id: Any, opmode: Any, key: tuple, run: Run, zero: tuple, setter: bool = False
) -> tuple[int, tuple]:
    """Run one command the way the legacy client and server would; returns (code, outputs)."""
    found = lookup(client_id)
    if found is None:
        return INIT, zero
    session, client = found
    mode = mode_of(opmode)
    if mode is None:
        return ILLEGAL, zero
    with session.lock:
        client.calls += 1
        if mode == REMOVE:
            had = client.replies.pop(key, None)
            return (OK if had is not None else NOVALUE), zero
        session.simulator.call(blocking=mode == BLOCKING)
        if mode == BUFFER:
            if key in client.streams and not setter:
                client.replies[key] = run_command(session, run, zero)
            return fetch(client, client.replies.get(key), zero)
        previous = client.replies.get(key)
        if setter and client.paused and mode != BLOCKING:
            client.queued.append((key, run, zero, mode))
            return fetch(client, previous, zero)
        reply = run_command(session, run, zero)
        if mode == BLOCKING:
            client.replies.pop(key, None)
            return fetch(client, reply, zero)
        if mode == STREAMING:
            active = key in client.streams
            client.streams[key] = (setter, run, zero)
            _rerun_after_reset(session)
            client.replies[key] = reply
            return fetch(client, reply if active else previous, zero)
        if mode == DISCONTINUE:
            client.streams.pop(key, None)
        client.replies[key] = reply
        return fetch(client, previous, zero)


def flush_queued(session: Session, client: Client) -> None:
    """Send the setters held while communication was paused, in one go (same pass)."""
    queued, client.queued = client.queued, []
    for key, run, zero, mode in queued:
        client.replies[key] = run_command(session, run, zero)
        if mode == STREAMING:
            client.streams[key] = (True, run, zero)
            _rerun_after_reset(session)
        elif mode == DISCONTINUE:
            client.streams.pop(key, None)


def _rerun_after_reset(session: Session) -> None:
    """Once a session has streams, a scene reset runs its setters again."""
    if reapply_setter_streams not in session.reset_hooks:
        session.reset_hooks.append(reapply_setter_streams)


def reapply_setter_streams(session: Session) -> None:
    """After a scene reset, streaming setters are executed again (the server re-runs streams)."""
    for client in list(session.clients.values()):
        for key, (setter, run, zero) in list(client.streams.items()):
            if setter:
                client.replies[key] = run_command(session, run, zero)
