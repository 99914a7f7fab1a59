"""The ZeroMQ remote API's own transport in front of ``ZmqServer``: CBOR over a ZeroMQ REP
socket on the loopback interface, as CoppeliaSim's add-on serves it (``PROTOCOL.md``).

The runner does not need this: scripts reach ``ZmqServer`` in process through the shim client.
It exists to prove the emulation against the real client (the PyPI package
``coppeliasim-zmqremoteapi-client``, which only speaks CBOR over ZeroMQ): the conformance test
runs the same calls through both clients and compares what they return. It needs ``pyzmq`` and
``cbor2`` (the ``test`` extra). It binds ``127.0.0.1`` only, on a port the system picks.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from ..client import Session
from .functions import server_for

POLL_MS = 50  # how often the serving thread looks at its stop flag


def _reply(session: Session, request: Any) -> dict[str, Any]:
    if not isinstance(request, dict):
        return {"err": "malformed request"}
    return server_for(session).handle(request)


@contextmanager
def loopback_server(session: Session) -> Iterator[int]:
    """Serve ``session`` on ``tcp://127.0.0.1:PORT`` while the block runs; yields PORT."""
    import cbor2
    import zmq

    context = zmq.Context()
    socket = context.socket(zmq.REP)
    socket.setsockopt(zmq.LINGER, 0)
    port = socket.bind_to_random_port("tcp://127.0.0.1")
    stop = threading.Event()
    failure: list[BaseException] = []

    def serve() -> None:
        poller = zmq.Poller()
        poller.register(socket, zmq.POLLIN)
        try:
            while not stop.is_set():
                if not poller.poll(POLL_MS):
                    continue
                raw = socket.recv()
                try:
                    reply = _reply(session, cbor2.loads(raw))
                except Exception as exc:  # a request the server could not decode
                    reply = {"err": f"malformed request: {exc}"}
                socket.send(cbor2.dumps(reply))
        except BaseException as exc:  # surfaced to the caller when the block ends
            failure.append(exc)

    thread = threading.Thread(target=serve, name="zmq-loopback-server", daemon=True)
    thread.start()
    try:
        yield port
    finally:
        stop.set()
        thread.join()
        socket.close()
        context.term()
    if failure:
        raise failure[0]
