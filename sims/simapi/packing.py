"""``sim.packTable``/``sim.unpackTable``: a Lua table as a byte string and back.

The byte layout is this emulation's own (tagged, little-endian, deterministic: dict keys sorted);
a table packed here unpacks here. CoppeliaSim's own layout only matters for data saved inside a
scene, and the scene readers do not load custom data blocks.
"""

from __future__ import annotations

import struct
from typing import Any

MAGIC = b"SGT1"


def pack(value: Any) -> bytes:
    out = bytearray(MAGIC)
    _put(out, value)
    return bytes(out)


def _put(out: bytearray, v: Any) -> None:
    if v is None:
        out += b"n"
    elif isinstance(v, bool):
        out += b"t" if v else b"f"
    elif isinstance(v, int):
        out += b"i" + struct.pack("<q", v)
    elif isinstance(v, float):
        out += b"d" + struct.pack("<d", v)
    elif isinstance(v, (bytes, bytearray, str)):
        raw = v.encode() if isinstance(v, str) else bytes(v)
        out += b"s" + struct.pack("<I", len(raw)) + raw
    elif isinstance(v, list):
        out += b"l" + struct.pack("<I", len(v))
        for item in v:
            _put(out, item)
    elif isinstance(v, dict):
        items = sorted(v.items(), key=lambda kv: (str(type(kv[0])), str(kv[0])))
        out += b"m" + struct.pack("<I", len(items))
        for k, item in items:
            _put(out, k)
            _put(out, item)
    else:
        raise ValueError(f"cannot pack a {type(v).__name__}")


def unpack(data: bytes) -> Any:
    if not data.startswith(MAGIC):
        raise ValueError("not a table packed by sim.packTable")
    value, end = _get(data, len(MAGIC))
    if end != len(data):
        raise ValueError("trailing bytes after the packed table")
    return value


def _get(data: bytes, i: int) -> tuple[Any, int]:
    tag = data[i : i + 1]
    i += 1
    if tag == b"n":
        return None, i
    if tag in (b"t", b"f"):
        return tag == b"t", i
    if tag == b"i":
        return struct.unpack_from("<q", data, i)[0], i + 8
    if tag == b"d":
        return struct.unpack_from("<d", data, i)[0], i + 8
    if tag == b"s":
        n = struct.unpack_from("<I", data, i)[0]
        return data[i + 4 : i + 4 + n], i + 4 + n
    if tag in (b"l", b"m"):
        n = struct.unpack_from("<I", data, i)[0]
        i += 4
        if tag == b"l":
            items = []
            for _ in range(n):
                item, i = _get(data, i)
                items.append(item)
            return items, i
        table = {}
        for _ in range(n):
            k, i = _get(data, i)
            table[k.decode() if isinstance(k, bytes) else k], i = _get(data, i)
        return table, i
    raise ValueError(f"bad packed table (tag {tag!r} at byte {i - 1})")
