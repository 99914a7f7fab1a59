"""The bridge a script in another Python (``--python``) uses when it has no client library of
its own: its ``sim``/``vrep`` and ZeroMQ modules (``foreign_shim/``, standard library only)
forward each call here, and it is answered by the same emulation an in-process script gets.

Why a bridge and not the client libraries' own protocols: a legacy script's ``sim.py`` needs
CoppeliaSim's native ``remoteApi`` library, which is not on PyPI and is not in the course's
repositories for Linux (they ship ``remoteApi.dll``), and the ZeroMQ client needs ``pyzmq``
and ``cbor2`` in the user's environment. When they are there, the script uses them instead and
talks to the real servers (``legacy_wire.py``, ``zmq/wire.py``); ``foreign_shim/bootstrap.py``
decides.

The bridge: one JSON object per line over TCP on 127.0.0.1. ``{"op": "hello"}`` gives the
constants and function names; ``{"op": "legacy", "fn", "args"}`` calls ``api.<fn>``;
``{"op": "zmq", "req"}`` hands a ZeroMQ request to ``ZmqServer.handle``; ``{"op": "keys",
"key"}`` plays the key file. Bytes travel as ``{"$b": base64}``, tuples as ``{"$t": [...]}``.
A line longer than ``MAX_LINE`` or not JSON ends that connection only.
"""

from __future__ import annotations

import base64
import contextlib
import json
import socket
import threading
from typing import Any

from .client import Session

LOOPBACK = "127.0.0.1"
MAX_LINE = 64 * 1024 * 1024


def encode(value: Any) -> Any:
    if isinstance(value, (bytes, bytearray)):
        tag = "$ba" if isinstance(value, bytearray) else "$b"
        return {tag: base64.b64encode(bytes(value)).decode("ascii")}
    if isinstance(value, tuple):
        return {"$t": [encode(v) for v in value]}
    if isinstance(value, list):
        return [encode(v) for v in value]
    if isinstance(value, dict):
        return {str(k): encode(v) for k, v in value.items()}
    if hasattr(value, "tolist") and not isinstance(value, str):
        return encode(value.tolist())
    return value


def decode(value: Any) -> Any:
    if isinstance(value, list):
        return [decode(v) for v in value]
    if isinstance(value, dict):
        if len(value) == 1:
            ((key, inner),) = value.items()
            if key == "$b":
                return base64.b64decode(inner)
            if key == "$ba":
                return bytearray(base64.b64decode(inner))
            if key == "$t":
                return tuple(decode(v) for v in inner)
            if key == "$a":  # a numpy array of one value (a number to ctypes, a list to loops)
                import numpy

                return numpy.array(decode(inner))
        return {k: decode(v) for k, v in value.items()}
    return value


def hello() -> dict[str, Any]:
    from . import api
    from .zmq.constants import CONSTANTS

    names = [n for n in api.__all__ if n.startswith("simx") and not n.startswith("simx_")]
    constants = {n: getattr(api, n) for n in api.__all__ if n.startswith(("simx_", "sim_"))}
    return {"functions": names, "constants": constants, "zmq_constants": CONSTANTS}


def answer(session: Session, message: dict[str, Any]) -> dict[str, Any]:
    op = message.get("op")
    try:
        if op == "hello":
            return {"ret": hello()}
        if op == "legacy":
            from . import api

            fn = str(message.get("fn", ""))
            if not fn.startswith("simx"):
                return {"exc": ["AttributeError", f"module 'sim' has no attribute {fn!r}"]}
            return {"ret": getattr(api, fn)(*decode(message.get("args") or []))}
        if op == "zmq":
            from .zmq.wire import answer as zmq_answer

            request = decode(message.get("req"))
            if not isinstance(request, dict):
                return {"ret": {"err": "malformed request (not a map)"}}
            return {"ret": zmq_answer(session, request)}
        if op == "keys":
            from sims.lua import keys

            return {"ret": keys.pressed_at(str(message.get("key", "")), session.clock.now())}
        return {"exc": ["ValueError", f"unknown operation {op!r}"]}
    except KeyboardInterrupt as exc:  # the key file ended: the script sees Ctrl+C
        return {"exc": ["KeyboardInterrupt", str(exc)]}
    except Exception as exc:
        return {"exc": [type(exc).__name__, str(exc)]}


class Bridge:
    """Serves the bridge for one session on a free loopback port (threads)."""

    def __init__(self, session: Session):
        self.session = session
        self.listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.listener.bind((LOOPBACK, 0))
        self.listener.listen(8)
        self.listener.settimeout(0.2)
        self.port = self.listener.getsockname()[1]
        self.stop_flag = threading.Event()
        self.threads: list[threading.Thread] = []
        self.conns: list[socket.socket] = []

    def start(self) -> Bridge:
        t = threading.Thread(target=self._accept, name="remote-api-bridge", daemon=True)
        t.start()
        self.threads.append(t)
        return self

    def stop(self) -> None:
        self.stop_flag.set()
        for sock in [self.listener, *self.conns]:
            with contextlib.suppress(OSError):
                sock.close()
        for t in self.threads:
            t.join(timeout=2.0)

    def _accept(self) -> None:
        while not self.stop_flag.is_set():
            try:
                conn, _ = self.listener.accept()
            except TimeoutError:
                continue
            except OSError:
                return
            conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self.conns.append(conn)
            t = threading.Thread(target=self._serve, args=(conn,), daemon=True)
            t.start()
            self.threads.append(t)

    def _serve(self, conn: socket.socket) -> None:
        from .client import SERVING

        SERVING.label = "the script (its own Python)"
        with contextlib.suppress(OSError, ValueError), conn.makefile("rb") as reader:
            while not self.stop_flag.is_set():
                line = reader.readline(MAX_LINE + 1)
                if not line or len(line) > MAX_LINE:
                    return
                message = json.loads(line)
                if not isinstance(message, dict):
                    return
                reply = answer(self.session, message)
                if "ret" in reply:
                    reply["ret"] = encode(reply["ret"])
                conn.sendall(json.dumps(reply).encode("utf-8") + b"\n")
