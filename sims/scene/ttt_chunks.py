"""The record layer of a decompressed ``.ttt`` body: named chunks and the values inside them.

What the file holds (from CoppeliaSim's serializer): a sequence of chunks, each a 3-character
name, a little-endian int32 byte count and that many bytes. The whole scene is such a sequence
ended by ``EOF`` (which has no count). An object's payload is itself a sequence ended by ``NXT``
(the common scene-object part) then one ended by ``EOO`` (the type's own part); nested parts
(meshes, colours, materials) are sequences ended by ``EOO``. Terminators carry no byte count.
Because every chunk says its length, a chunk we do not know is skipped exactly.

Values are little-endian: ``int32``, ``float32`` (chunk names in capitals, e.g. ``Cfq``, the
float format of V-REP 3.x and CoppeliaSim up to 4.3) or ``float64`` (names starting with ``_``,
e.g. ``_fq``, CoppeliaSim 4.4 and later); strings are an int32 length and bytes.
"""

from __future__ import annotations

import struct
from collections.abc import Iterator
from typing import NamedTuple

TERMINATORS = (b"EOO", b"NXT")
_HEADER = struct.Struct("<3si")


class ChunkError(ValueError):
    """The chunk structure is broken (a length runs past its container): corrupt data."""


class Chunk(NamedTuple):
    name: str
    start: int  # first payload byte
    end: int  # one past the last payload byte


def chunk_list(buf: bytes, pos: int, end: int) -> tuple[list[Chunk], int]:
    """Read chunks from ``pos`` up to a terminator (``EOO``/``NXT``) or ``end``; return them and
    the position after the terminator."""
    out: list[Chunk] = []
    unpack = _HEADER.unpack_from
    while pos < end:
        if pos + 7 > end:
            if buf[pos : pos + 3] in TERMINATORS:
                return out, pos + 3
            raise ChunkError(f"chunk header runs past its container at byte {pos}")
        name, size = unpack(buf, pos)
        if name in TERMINATORS:
            return out, pos + 3
        if size < 0 or pos + 7 + size > end:
            raise ChunkError(
                f"chunk {name.decode('latin-1')!r} at byte {pos} claims {size} bytes, "
                f"only {end - pos - 7} are left"
            )
        out.append(Chunk(name.decode("latin-1"), pos + 7, pos + 7 + size))
        pos += 7 + size
    return out, pos


def top_level(buf: bytes) -> Iterator[Chunk]:
    """The scene's top-level chunks, up to ``EOF``, one at a time (raises :class:`ChunkError`
    where the structure breaks)."""
    pos = 0
    end = len(buf)
    while True:
        if pos + 3 > end:
            raise ChunkError("the scene data ends without its end marker (EOF)")
        name = buf[pos : pos + 3]
        if name == b"EOF":
            return
        if pos + 7 > end:
            raise ChunkError(f"chunk header runs past the end at byte {pos}")
        (size,) = struct.unpack_from("<i", buf, pos + 3)
        if size < 0 or pos + 7 + size > end:
            raise ChunkError(
                f"chunk {name.decode('latin-1')!r} at byte {pos} claims {size} bytes, "
                f"only {end - pos - 7} are left"
            )
        yield Chunk(name.decode("latin-1"), pos + 7, pos + 7 + size)
        pos += 7 + size


class Fields:
    """Reads values one after the other from a chunk's payload, never past its end."""

    def __init__(self, buf: bytes, chunk: Chunk):
        self.buf = buf
        self.pos = chunk.start
        self.end = chunk.end
        self.name = chunk.name

    def _take(self, fmt: str) -> tuple:
        size = struct.calcsize(fmt)
        if self.pos + size > self.end:
            raise ChunkError(f"chunk {self.name!r} is shorter than its fields")
        vals = struct.unpack_from(fmt, self.buf, self.pos)
        self.pos += size
        return vals

    def i32(self) -> int:
        return self._take("<i")[0]

    def u8(self) -> int:
        return self._take("<B")[0]

    def u16(self) -> int:
        return self._take("<H")[0]

    def f32(self, n: int = 1) -> tuple[float, ...]:
        return self._take(f"<{n}f")

    def f64(self, n: int = 1) -> tuple[float, ...]:
        return self._take(f"<{n}d")

    def real(self, n: int = 1) -> tuple[float, ...]:
        """Floats in the chunk's own precision: float64 for ``_xx`` chunks, float32 otherwise."""
        return self.f64(n) if self.name.startswith("_") else self.f32(n)

    def string(self) -> str:
        n = self.i32()
        if n < 0 or self.pos + n > self.end:
            raise ChunkError(f"chunk {self.name!r} holds a string longer than itself")
        raw = bytes(self.buf[self.pos : self.pos + n])
        self.pos += n
        return raw.decode("utf-8", errors="replace")

    def rest(self) -> bytes:
        raw = bytes(self.buf[self.pos : self.end])
        self.pos = self.end
        return raw


def bit(value: int, n: int) -> bool:
    return bool(value & (1 << n))
