"""The legacy remote API server on TCP (CoppeliaSim's ``remoteApiServerSide``), loopback only.

A script's ``remoteApi.so`` (or ``.dll``), the client library CoppeliaSim's ``sim.py`` loads,
connects here unchanged: its communication thread sends a message every few milliseconds (its
queued commands, or none) and reads one reply, which holds the replies to those commands and
the current values of every command it streams. Commands are carried out by
``legacy_commands`` on a connection slot of the session (``Session.connect``).

Operation modes, as the server sees them: oneshot and blocking commands are carried out and
answered once; a streaming command is carried out now and then again whenever a simulation
pass has happened since, and answered in every reply until a discontinue command for it
arrives (carried out once more; the client drops that reply); split commands are put together
from their chunks first. ``simx_cmd_kill_connection`` (``simxFinish``) ends the connection.

Bad input never stops the server: a malformed packet or message, or one larger than
``MAX_MESSAGE``, ends that client's connection only. Ports are bound on 127.0.0.1 only.
"""

from __future__ import annotations

import contextlib
import socket
import threading
from dataclasses import dataclass, field

from .client import Session
from .legacy_codec import (
    MAX_MESSAGE,
    PACKET_HEADER,
    Command,
    ProtocolError,
    command_bytes,
    message_bytes,
    packets,
    parse_message,
    read_packet_header,
)
from .legacy_commands import run_command

LOOPBACK = "127.0.0.1"
CONTINUOUS_PORT = 19997  # remoteApiConnections.txt's default
KILL_CONNECTION = 0x000A
STREAMING, STREAMING_SPLIT, DISCONTINUE = 0x020000, 0x040000, 0x050000
IDLE_TIMEOUT = 3600.0  # s: a client silent this long is dropped


@dataclass
class _Stream:
    cmd: Command
    reply: bytes = b""
    at_pass: int = -1


@dataclass
class _Connection:
    cid: int
    streams: dict[tuple[int, bytes], _Stream] = field(default_factory=dict)
    partial: dict[tuple[int, bytes], bytearray] = field(default_factory=dict)


def _recv_exact(sock: socket.socket, n: int) -> bytes:
    data = bytearray()
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            raise ConnectionError("client closed the connection")
        data += chunk
    return bytes(data)


def read_message(sock: socket.socket) -> bytes:
    """One message (its packets put together)."""
    data = bytearray()
    while True:
        length, left = read_packet_header(_recv_exact(sock, PACKET_HEADER))
        data += _recv_exact(sock, length)
        if len(data) > MAX_MESSAGE:
            raise ProtocolError(f"message larger than {MAX_MESSAGE} bytes")
        if left == 0:
            return bytes(data)


class LegacyWire:
    """Serves one session's legacy remote API on the given ports (a thread each, plus one per
    connected client)."""

    def __init__(self, session: Session, ports: tuple[int, ...] = (CONTINUOUS_PORT,)):
        self.session = session
        self.listeners: list[socket.socket] = []
        for port in ports:
            sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            sock.bind((LOOPBACK, port))
            sock.listen(16)
            sock.settimeout(0.2)
            self.listeners.append(sock)
        self.ports = tuple(s.getsockname()[1] for s in self.listeners)
        self.stop_flag = threading.Event()
        self.threads: list[threading.Thread] = []
        self.clients: list[socket.socket] = []

    def start(self) -> LegacyWire:
        for sock in self.listeners:
            t = threading.Thread(target=self._accept, args=(sock,), daemon=True, name="extapi")
            t.start()
            self.threads.append(t)
        return self

    def stop(self) -> None:
        self.stop_flag.set()
        for sock in [*self.listeners, *self.clients]:
            with contextlib.suppress(OSError):
                sock.close()
        for t in self.threads:
            t.join(timeout=2.0)

    def _accept(self, listener: socket.socket) -> None:
        port = listener.getsockname()[1]
        while not self.stop_flag.is_set():
            try:
                conn, _addr = listener.accept()
            except TimeoutError:
                continue
            except OSError:
                return
            conn.settimeout(IDLE_TIMEOUT)
            conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self.clients.append(conn)
            t = threading.Thread(target=self._serve, args=(conn, port), daemon=True)
            t.start()
            self.threads.append(t)

    def _serve(self, conn: socket.socket, port: int) -> None:
        from .client import SERVING

        SERVING.label = f"legacy client on port {port}"
        session = self.session
        with session.lock:
            session.simulator.choose_server(port)
            cid = session.connect(LOOPBACK, port, api="legacy-wire")
        if cid < 0:  # no slot, or no server on this port in the scene: refuse, as CoppeliaSim
            with contextlib.suppress(OSError):
                conn.close()
            return
        state = _Connection(cid)
        try:
            while not self.stop_flag.is_set():
                raw = read_message(conn)
                reply, done = self._answer(state, raw)
                conn.sendall(reply)
                if done:
                    return
        except (OSError, ConnectionError, ProtocolError):
            return  # this client only: the server goes on
        finally:
            with contextlib.suppress(OSError):
                conn.close()
            session.finish(cid)

    def _answer(self, state: _Connection, raw: bytes) -> tuple[bytes, bool]:
        header, commands = parse_message(raw)
        session, sim = self.session, self.session.simulator
        out: list[bytes] = []
        done = False
        answered: set[tuple[int, bytes]] = set()
        for cmd in commands:
            if cmd.code == KILL_CONNECTION:
                done = True
                continue
            cmd = self._whole(state, cmd)
            if cmd is None:
                continue  # a split command still arriving
            error, pure = run_command(state.cid, cmd)
            piece = command_bytes(cmd, pure, sim.sim_time * 1000, error)
            if cmd.mode in (STREAMING, STREAMING_SPLIT):
                state.streams[cmd.key] = _Stream(cmd, piece, sim.passes)
            elif cmd.mode == DISCONTINUE:
                state.streams.pop(cmd.key, None)
            answered.add(cmd.key)
            out.append(piece)
        for key, stream in list(state.streams.items()):
            if key in answered:
                continue
            if stream.at_pass != sim.passes:  # the simulation moved: the value may have too
                error, pure = run_command(state.cid, stream.cmd)
                stream.reply = command_bytes(stream.cmd, pure, sim.sim_time * 1000, error)
                stream.at_pass = sim.passes
            out.append(stream.reply)
        server_state = _state_bits(sim)
        message = message_bytes(header, out, session.clock.now() * 1000, server_state)
        return packets(message), done

    def _whole(self, state: _Connection, cmd: Command) -> Command | None:
        """A split command's chunks put together (None until its last chunk arrived)."""
        whole = cmd.full_size - 26 - len(cmd.ident)
        if whole <= len(cmd.pure) and cmd.offset == 0:
            return cmd
        if whole > MAX_MESSAGE:
            raise ProtocolError("split command larger than the message limit")
        buf = state.partial.setdefault(cmd.key, bytearray(whole))
        end = cmd.offset + len(cmd.pure)
        if len(buf) != whole or end > whole:
            state.partial.pop(cmd.key, None)
            raise ProtocolError("split command chunks do not fit together")
        buf[cmd.offset : end] = cmd.pure
        if end < whole:
            return None
        del state.partial[cmd.key]
        return Command(cmd.code, cmd.mode, cmd.delay, cmd.ident, bytes(buf), cmd.options)


def _state_bits(sim) -> int:
    """The reply header's server state: bit 0 simulation not stopped, 1 paused, 2 real time."""
    bits = 0 if sim.state == "stopped" else 1
    if sim.state == "paused":
        bits |= 2
    if sim.clock.realtime:
        bits |= 4
    return bits
