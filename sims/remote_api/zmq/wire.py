"""CoppeliaSim's ZeroMQ remote API on the wire: CBOR requests over ZeroMQ, loopback only.

Real clients (the PyPI ``coppeliasim-zmqremoteapi-client``, its asyncio form, the C++/Java/
Matlab clients) connect a REQ socket and exchange CBOR maps (``PROTOCOL.md`` of
CoppeliaRobotics/zmqRemoteApi): ``{"func", "args", "uuid", ...}`` in, ``{"ret": [...]}`` or
``{"err": "..."}`` out; ``{"func": "_*end*_"}`` says goodbye. Requests are answered by the
session's ``ZmqServer`` (the same one in-process scripts use), so both see the same World.

Why a ROUTER socket where CoppeliaSim's add-on uses REP: a REQ client cannot tell them apart,
and a ROUTER may hold one client's reply while it serves the others. That is what ``sim.step``
needs with several stepping clients (CoppeliaSim's add-on has the client poll with
``_*wait*_`` instead). Requests are answered in the server's thread; a ``sim.step`` that must
wait for the other stepping clients is parked (its reply sent once the pass is done), and a
function that steps inside (``sim.moveToConfig``...) runs in a thread of the client's own
(``_Worker``), in order, waiting there only.

Limits (bad input never stops the server): a message larger than ``MAX_REQUEST`` bytes makes
ZeroMQ drop that peer's connection (``MAXMSGSIZE``); a request that is not CBOR, not a map,
or has no ``func`` gets an ``err`` reply, as CoppeliaSim's add-on answers one; the server binds
127.0.0.1 only. Needs ``pyzmq`` and ``cbor2`` (the ``serve`` extra).
"""

from __future__ import annotations

import contextlib
import functools
import itertools
import queue
import threading
from collections.abc import Iterator
from typing import Any

from ..client import Session
from ..server import CONTINUOUS_PORT
from .functions import server_for
from .server import INLINE, Park

LOOPBACK = "127.0.0.1"
DEFAULT_PORT = 23000  # CoppeliaSim's ZeroMQ remote API port (23001: its control port)
MAX_REQUEST = 64 * 1024 * 1024  # bytes: a bigger message drops the connection (MAXMSGSIZE)
POLL_MS = 50  # how often the serving thread looks at its stop flag
PARKED_POLL_MS = 1  # ... and at the parked sim.step calls, while there are some

#: Functions that may step the simulation inside (run in the client's own thread). sim.step is
#: answered inline and parked when it must wait.
MAY_WAIT = frozenset(
    "sim.moveToConfig sim.moveToPose sim.wait sim.waitForSignal sim.switchThread sim.yield "
    "sim.moveToConfig_step sim.moveToPose_step".split()
)


@functools.cache
def _may_wait() -> frozenset[str]:
    """The blocking functions of the sim.* table when it declares them, else ``MAY_WAIT``."""
    try:
        from sims.simapi.table import BLOCKING  # type: ignore[import-not-found]
    except ImportError:
        return MAY_WAIT
    return MAY_WAIT | (frozenset(BLOCKING) - {"sim.step"})


_IDS = itertools.count(1)


def decode(raw: bytes) -> dict[str, Any] | str:
    """A request, or the error text to answer a malformed one with."""
    import cbor2

    try:
        request = cbor2.loads(raw)
    except Exception as exc:  # cbor2 raises several kinds for broken input
        return f"malformed request (not CBOR: {type(exc).__name__})"
    if not isinstance(request, dict):
        return "malformed request (not a map)"
    if not isinstance(request.get("func"), str):
        return "malformed request (no 'func' string)"
    return request


def encode(reply: dict[str, Any]) -> bytes:
    import cbor2

    try:
        return cbor2.dumps(reply)
    except Exception as exc:  # a value the emulation returned that CBOR cannot carry
        return cbor2.dumps({"err": f"cannot encode the reply: {exc}"})


def answer(session: Session, request: dict[str, Any]) -> dict[str, Any]:
    """The reply to one decoded request (``_*end*_`` ends the client's stepping)."""
    server = server_for(session)
    sim = session.simulator
    if sim is not None and sim.server_auto and sim.world is None:
        with session.lock:  # CoppeliaSim's ZeroMQ add-on serves while stopped: continuous
            sim.choose_server(CONTINUOUS_PORT)
    if request.get("func") == "_*end*_":
        with session.lock:
            server.end_client(str(request.get("uuid", "")))
        return {}
    if request.get("func") == "_*executed*_":  # a client answering a wait we never sent
        return {"ret": []}
    return server.handle(request)


class _Worker(threading.Thread):
    """One client's requests, in order, in a thread of its own (it may wait in sim.step)."""

    def __init__(self, wire: ZmqWire, identity: bytes):
        super().__init__(name=f"zmq-client-{next(_IDS)}", daemon=True)
        self.wire, self.identity = wire, identity
        self.inbox: queue.SimpleQueue[bytes | None] = queue.SimpleQueue()
        self.uuid = ""

    def run(self) -> None:
        from ..client import SERVING

        SERVING.label = "ZeroMQ client"
        push = self.wire.context.socket(self.wire.zmq.PUSH)
        push.setsockopt(self.wire.zmq.LINGER, 0)
        push.connect(self.wire.outbox_address)
        try:
            while True:
                raw = self.inbox.get()
                if raw is None:
                    return
                request = decode(raw)
                if isinstance(request, str):
                    reply: dict[str, Any] = {"err": request}
                else:
                    self.uuid = str(request.get("uuid", self.uuid))
                    try:
                        reply = answer(self.wire.session, request)
                    except Exception as exc:  # never let one client take the server down
                        reply = {"err": f"internal error: {type(exc).__name__}: {exc}"}
                push.send_multipart([self.identity, b"", encode(reply)])
        finally:
            push.close()


class ZmqWire:
    """Serves one session's ``ZmqServer`` on ``tcp://127.0.0.1:PORT`` (a thread of its own)."""

    def __init__(self, session: Session, port: int | None = DEFAULT_PORT):
        import zmq

        self.zmq, self.session = zmq, session
        self.context = zmq.Context()
        self.socket = self.context.socket(zmq.ROUTER)
        self.socket.setsockopt(zmq.LINGER, 0)
        self.socket.setsockopt(zmq.MAXMSGSIZE, MAX_REQUEST)
        if port is None:
            self.port = self.socket.bind_to_random_port(f"tcp://{LOOPBACK}")
        else:
            self.socket.bind(f"tcp://{LOOPBACK}:{port}")
            self.port = port
        self.outbox_address = f"inproc://sitegen-zmq-replies-{id(self)}"
        self.outbox = self.context.socket(zmq.PULL)
        self.outbox.bind(self.outbox_address)
        self.workers: dict[bytes, _Worker] = {}
        self.parked: list[tuple[bytes, int]] = []  # sim.step replies waiting for their pass
        self.stop_flag = threading.Event()
        self.failure: BaseException | None = None
        self.thread = threading.Thread(target=self._serve, name="zmq-wire", daemon=True)

    def start(self) -> ZmqWire:
        self.thread.start()
        return self

    def _serve(self) -> None:
        zmq = self.zmq
        poller = zmq.Poller()
        poller.register(self.socket, zmq.POLLIN)
        poller.register(self.outbox, zmq.POLLIN)
        try:
            while not self.stop_flag.is_set():
                ready = dict(poller.poll(PARKED_POLL_MS if self.parked else POLL_MS))
                if self.outbox in ready:
                    while True:
                        try:
                            frames = self.outbox.recv_multipart(zmq.NOBLOCK)
                        except zmq.Again:
                            break
                        self.socket.send_multipart(frames)
                if self.socket in ready:
                    while True:
                        try:
                            frames = self.socket.recv_multipart(zmq.NOBLOCK)
                        except zmq.Again:
                            break
                        self._dispatch(frames)
                self._release_parked()
        except BaseException as exc:  # surfaced by stop()
            self.failure = exc

    def _dispatch(self, frames: list[bytes]) -> None:
        """Answer a request here (most are quick), park a ``sim.step`` that must wait for the
        other clients, and hand a function that may step inside to the client's own thread."""
        if len(frames) != 3 or frames[1] != b"":  # not a REQ envelope: nothing to answer
            return
        identity, raw = frames[0], frames[2]
        request = decode(raw)
        if isinstance(request, dict) and request.get("func") in _may_wait():
            worker = self.workers.get(identity)
            if worker is None:
                worker = self.workers[identity] = _Worker(self, identity)
                worker.start()
            worker.inbox.put(raw)
            return
        if isinstance(request, str):
            reply: dict[str, Any] = {"err": request}
        else:
            INLINE.on = True
            try:
                reply = answer(self.session, request)
            except Park as park:
                self.parked.append((identity, park.target))
                return
            except Exception as exc:  # never let one client take the server down
                reply = {"err": f"internal error: {type(exc).__name__}: {exc}"}
            finally:
                INLINE.on = False
        self.socket.send_multipart([identity, b"", encode(reply)])

    def _release_parked(self) -> None:
        """Answer the parked ``sim.step`` calls whose pass has happened (or cannot come)."""
        if not self.parked:
            return
        sim = self.session.simulator
        with self.session.lock:
            done = sim.state != "running" or sim.world is None
            ready = [p for p in self.parked if done or sim.passes >= p[1]]
        for item in ready:
            self.parked.remove(item)
            self.socket.send_multipart([item[0], b"", encode({"ret": [None]})])

    def stop(self) -> None:
        self.stop_flag.set()
        if self.thread.is_alive():
            self.thread.join()
        for worker in self.workers.values():
            worker.inbox.put(None)
        server = server_for(self.session)
        with self.session.lock:  # wake workers waiting for a pass that will not come
            server.closing = True
            server.cond.notify_all()
        for worker in self.workers.values():
            worker.join(timeout=2.0)
        with self.session.lock:
            server.closing = False
            for worker in self.workers.values():
                server.end_client(worker.uuid)
        self.socket.close()
        self.outbox.close()
        if any(w.is_alive() for w in self.workers.values()):
            self.context.destroy(linger=0)
        else:
            self.context.term()
        if self.failure is not None:
            raise self.failure


@contextlib.contextmanager
def loopback_server(session: Session, port: int | None = None) -> Iterator[int]:
    """Serve ``session`` on ``tcp://127.0.0.1:PORT`` while the block runs; yields PORT (a
    free one the system picks unless ``port`` is given)."""
    wire = ZmqWire(session, port).start()
    try:
        yield wire.port
    finally:
        wire.stop()
