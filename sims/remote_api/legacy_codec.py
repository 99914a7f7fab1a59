"""The byte format of CoppeliaSim's legacy remote API (``extApi``, remoteApi.so/.dll): packets,
messages and commands, read and written as the server side does.

Written from the format the client library uses (CoppeliaRobotics/remoteApi ``extApi.c`` and
the ``simx_*`` offsets in CoppeliaSim's ``simConst.h``); no code of theirs is used. Everything
is little-endian (the client's first packet word, 1, lets a server detect that).

- A **packet** on the TCP stream: 6-byte header (short 1, short payload length, short packets
  left after this one) + payload of at most ``MAX_PACKET - 6`` bytes; a message is the
  payloads of consecutive packets until "packets left" is 0.
- A **message**: an 18-byte header (CRC, version, message id, client time, server time,
  scene id, server state) + commands back to back.
- A **command**: a 26-byte sub-header (size, full size, identification data size, split
  offset, command code | operation mode, delay or split size, simulation time, status,
  reserved) + identification data (what tells two commands of one kind apart: a handle, two
  ints, a name, or an int and two names) + pure data (arguments, or the reply's values).

Bad input raises ``ProtocolError``; the server then drops that one connection.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

HEADER = 18  # SIMX_HEADER_SIZE
SUBHEADER = 26  # SIMX_SUBHEADER_SIZE
PACKET_HEADER = 6
MAX_PACKET = 1300  # SOCKET_MAX_PACKET_SIZE of the client library
MAX_MESSAGE = 64 * 1024 * 1024  # bytes: a larger message is refused (the connection dropped)
CMD_MASK = 0x00FFFF
VERSION = 11  # SIMX_VERSION of the last client library

# command code ranges: what the identification data of a command is
NULL_START, INT_START, INT_CUSTOM, INTINT_START, INTINT_CUSTOM = (
    0x0000,
    0x1000,
    0x1800,
    0x2000,
    0x2800,
)
STRING_START, INT2STRINGS_START, INT2STRINGS_END, STRING_CUSTOM, RESERVED = (
    0x3000,
    0x3400,
    0x3500,
    0x3800,
    0x4000,
)

_SUB = struct.Struct("<iiHiiHiBB")  # the sub-header, 26 bytes
_HDR = struct.Struct("<HBiiiHB")  # the message header, 18 bytes


class ProtocolError(ValueError):
    """Bytes that are not a legacy remote API message."""


@dataclass
class Command:
    """One command of a message: ``code`` (without the mode), ``mode`` (operation mode bits),
    ``ident`` (identification data), ``pure`` (the rest), ``options`` (client status byte)."""

    code: int
    mode: int
    delay: int
    ident: bytes
    pure: bytes
    options: int = 0
    full_size: int = 0  # > the chunk's size when a split command arrives in parts
    offset: int = 0  # where this chunk's pure data goes (split commands)

    @property
    def key(self) -> tuple[int, bytes]:
        """What the client matches replies by: the command code and its identification."""
        return self.code, self.ident


@dataclass
class Header:
    message_id: int
    client_time: int


def ident_size(code: int, data: bytes) -> int:
    """The size of a command's identification data, from its code (as the client computes
    it), reading the names it holds. Raises ProtocolError when they are not terminated."""

    def cstring(at: int) -> int:
        end = data.find(b"\0", at)
        if end < 0:
            raise ProtocolError(f"command {code:#06x}: unterminated name")
        return end + 1 - at

    if INT_START < code < INTINT_START:
        return 4
    if INTINT_START < code < STRING_START:
        return 8
    if STRING_START < code < INT2STRINGS_START:
        return cstring(0)
    if INT2STRINGS_START < code < INT2STRINGS_END:
        first = cstring(4)
        return 4 + first + cstring(4 + first)
    return 0


def parse_message(data: bytes) -> tuple[Header, list[Command]]:
    if len(data) < HEADER:
        raise ProtocolError(f"message of {len(data)} bytes: shorter than its header")
    _crc, _version, message_id, client_time, _t, _scene, _state = _HDR.unpack_from(data, 0)
    commands: list[Command] = []
    at = HEADER
    while at < len(data):
        if len(data) - at < SUBHEADER:
            raise ProtocolError("a command shorter than its sub-header")
        size, full, _pd0, offset1, raw, delay, _time, status, _r = _SUB.unpack_from(data, at)
        if size < SUBHEADER or at + size > len(data) or full < size:
            raise ProtocolError(f"a command's size ({size}) does not fit the message")
        body = data[at + SUBHEADER : at + size]
        code = raw & CMD_MASK
        n = ident_size(code, body)
        if n > len(body):
            raise ProtocolError(f"command {code:#06x}: identification data cut short")
        commands.append(
            Command(code, raw - code, delay, body[:n], body[n:], status, full, max(0, offset1))
        )
        at += size
    return Header(message_id, client_time), commands


def command_bytes(cmd: Command, pure: bytes, sim_time_ms: int, error: bool) -> bytes:
    """A reply command: the request's code, mode and identification, then ``pure``."""
    size = SUBHEADER + len(cmd.ident) + len(pure)
    sub = _SUB.pack(
        size,
        size,
        len(cmd.ident),
        0,
        cmd.code + cmd.mode,
        cmd.delay,
        int(sim_time_ms),
        1 if error else 0,
        0,
    )
    return sub + cmd.ident + pure


def message_bytes(header: Header, commands: list[bytes], server_ms: int, state: int) -> bytes:
    head = _HDR.pack(
        0, VERSION, header.message_id, header.client_time, int(server_ms) & 0x7FFFFFFF, 1, state
    )
    return head + b"".join(commands)


def packets(message: bytes) -> bytes:
    """The message cut into packets, as the stream carries it."""
    room = MAX_PACKET - PACKET_HEADER
    chunks = [message[i : i + room] for i in range(0, len(message), room)] or [b""]
    out = []
    for n, chunk in enumerate(chunks):
        out.append(struct.pack("<hhh", 1, len(chunk), len(chunks) - 1 - n) + chunk)
    return b"".join(out)


def read_packet_header(head: bytes) -> tuple[int, int]:
    """(payload length, packets left) from a 6-byte packet header."""
    one, length, left = struct.unpack("<hhh", head)
    if one != 1:
        raise ProtocolError("packet header: not a little-endian remote API client")
    if length <= 0 or length > MAX_PACKET - PACKET_HEADER or left < 0:
        raise ProtocolError(f"packet header: length {length}, packets left {left}")
    return length, left


# --- values in pure data ------------------------------------------------------------------------
def ints(data: bytes, count: int | None = None) -> list[int]:
    n = len(data) // 4 if count is None else count
    if len(data) < 4 * n:
        raise ProtocolError("arguments cut short")
    return list(struct.unpack_from(f"<{n}i", data))


def floats(data: bytes, count: int | None = None, at: int = 0) -> list[float]:
    n = (len(data) - at) // 4 if count is None else count
    if len(data) < at + 4 * n:
        raise ProtocolError("arguments cut short")
    return list(struct.unpack_from(f"<{n}f", data, at))


def cstrings(data: bytes) -> list[str]:
    """Zero-terminated names, decoded (a trailing part without its zero is kept)."""
    parts = data.split(b"\0")
    if parts and parts[-1] == b"":
        parts.pop()
    return [p.decode("utf-8", "replace") for p in parts]


def pack_ints(values) -> bytes:
    values = [int(v) for v in values]
    return struct.pack(f"<{len(values)}i", *values)


def pack_floats(values) -> bytes:
    values = [float(v) for v in values]
    return struct.pack(f"<{len(values)}f", *values)
