"""Builders for synthetic CoppeliaSim scene files, for the scene-reader tests.

They write the binary ``.ttt`` layout described in ``sims/scene/ttt*.py`` (header, Huffman
compression, chunks) so that tests can make small, exact, and deliberately broken files without
CoppeliaSim. The Huffman encoder follows the file format (tree depth first, "0" branch first,
bits most significant first); it shares no code with the decoder under test.
"""

from __future__ import annotations

import heapq
import struct


def huffman_compress(data: bytes) -> bytes:
    counts: dict[int, int] = {}
    for b in data:
        counts[b] = counts.get(b, 0) + 1
    bits: list[str] = []
    if len(counts) == 1:
        (sym,) = counts
        bits.append("1" + format(sym, "08b"))
        bits.append("0" * len(data))  # one-leaf tree: each symbol written as one bit
    else:
        heap: list = [(n, i, ("leaf", s)) for i, (s, n) in enumerate(sorted(counts.items()))]
        heapq.heapify(heap)
        order = len(heap)
        while len(heap) > 1:
            n1, _, a = heapq.heappop(heap)
            n2, _, b = heapq.heappop(heap)
            heapq.heappush(heap, (n1 + n2, order, ("node", a, b)))
            order += 1
        root = heap[0][2]
        codes: dict[int, str] = {}

        def walk(node, prefix: str) -> None:
            if node[0] == "leaf":
                bits.append("1" + format(node[1], "08b"))
                codes[node[1]] = prefix
            else:
                bits.append("0")
                walk(node[1], prefix + "0")
                walk(node[2], prefix + "1")

        walk(root, "")
        bits.append("".join(codes[b] for b in data))
    stream = "".join(bits)
    stream += "0" * (-len(stream) % 8)
    return int(stream, 2).to_bytes(len(stream) // 8, "big") if stream else b""


def chunk(name: str, payload: bytes) -> bytes:
    assert len(name) == 3
    return name.encode() + struct.pack("<i", len(payload)) + payload


def floats(*vals: float) -> bytes:
    return struct.pack(f"<{len(vals)}f", *vals)


def ints(*vals: int) -> bytes:
    return struct.pack(f"<{len(vals)}i", *vals)


def string(text: str) -> bytes:
    raw = text.encode()
    return struct.pack("<i", len(raw)) + raw


def scramble(text: bytes) -> bytes:
    """CoppeliaSim's light scrambling of script text (the inverse of the reader's)."""
    buf = bytearray(text)
    n = len(buf)
    if n < 3:
        return bytes(buf)
    s8 = lambda v: v - 256 if v > 127 else v  # noqa: E731
    start = int(s8(buf[0]) / 2)
    end = s8(buf[-1]) * 3
    for i in range(1, n - 1):
        v = buf[i]
        if i & 4:
            v -= i // 2 + end
        if i & 2:
            v += 3 * i + start
        if i & 1:
            v -= i + start + end
        buf[i] = v & 0xFF
    return bytes(buf)


def scene_object(
    kind: str,
    handle: int,
    name: str,
    own: list[bytes],
    parent: int = -1,
    quat_wxyz: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0),
    position: tuple[float, float, float] = (0.0, 0.0, 0.0),
    alias: str = "",
) -> bytes:
    common = (
        chunk("3do", b"\x00\x00\x00")
        + chunk("Cfq", floats(*quat_wxyz, *position))
        + chunk("Ids", ints(handle, parent))
        + chunk("Nme", string(name))
        + chunk("Lar", struct.pack("<H", 1))
        + (chunk("Ali", string(alias)) if alias else b"")
        + b"NXT"
    )
    return chunk(kind, common + b"".join(own) + b"EOO")


def ttt_file(
    body: bytes,
    version: int = 22,
    oldest_reader: int = 18,
    compress: bool = True,
    program: int = 40100,
) -> bytes:
    data = body + b"EOF"
    payload = huffman_compress(data) if compress else data
    header = b"VREP" + struct.pack("<ii", version, oldest_reader)
    header += bytes([1 if compress else 0]) + struct.pack("<i", len(data))
    header += struct.pack("<i", 0) + struct.pack("<H", program) + struct.pack("<I", 0x1001)
    header += b"\x01\x01" + b"\x00" * 992
    assert len(header) == 1021
    return header + payload
