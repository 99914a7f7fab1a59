"""Custom data blocks saved in a ``.ttt`` file (what ``sim.readCustomDataBlock`` reads back).

Two layouts, as coppeliaSimLib serializes them (``CCustomData``, ``CCustomData_old``, read for
this): an object's ``Cda`` chunk (a scene's ``CDA``) holds ``Cdt`` items (tag string, byte
count, bytes); the older ``Cod`` (``CDS``) holds ``Dat`` items (header number, byte count,
bytes), where header 356248756 packs tagged blocks (size, name length, name, data each) and any
other header is kept under the tag ``_oldObjectCustomData_<header>_`` as CoppeliaSim converts
it. Readers run nothing: this only copies bytes.
"""

from __future__ import annotations

import struct

from sims.scene.model import CustomData
from sims.scene.ttt_chunks import Chunk, Fields, chunk_list

TAGGED = 356248756


def blocks(buf: bytes, chunk: Chunk, owner: str) -> list[CustomData]:
    """The blocks of one ``Cda``/``CDA`` (new) or ``Cod``/``CDS`` (old) chunk."""
    items, _ = chunk_list(buf, chunk.start, chunk.end)
    out: list[CustomData] = []
    for item in items:
        f = Fields(buf, item)
        if item.name == "Cdt":
            tag = f.string()
            n = f.i32()
            out.append(CustomData(owner, tag, bytes(buf[f.pos : f.pos + n]).hex()))
        elif item.name == "Dat":
            header, n = f.i32(), f.i32()
            data = bytes(buf[f.pos : f.pos + n])
            if header == TAGGED:
                out += _tagged(data, owner)
            else:
                kind = "Object" if owner else "Scene"
                out.append(CustomData(owner, f"_old{kind}CustomData_{header}_", data.hex()))
    return out


def _tagged(data: bytes, owner: str) -> list[CustomData]:
    out = []
    off = 0
    while off + 8 < len(data):
        size, name_len = struct.unpack_from("<ii", data, off)
        if size <= 8 or off + size > len(data):
            break
        name = data[off + 8 : off + 8 + name_len].split(b"\0")[0].decode("utf-8", "replace")
        payload = data[off + 8 + name_len : off + size]
        if payload:
            out.append(CustomData(owner, name, payload.hex()))
        off += size
    return out


def object_blocks(buf: bytes, chunk: Chunk, owner: str) -> list[CustomData]:
    """The custom data of an object chunk (its common part's ``Cda``, else ``Cod``)."""
    base, _ = chunk_list(buf, chunk.start, chunk.end)
    new = [c for c in base if c.name == "Cda"]
    old = [c for c in base if c.name == "Cod"]
    found: list[CustomData] = []
    for c in new or old:
        found += blocks(buf, c, owner)
    return found


def script_parameters(buf: bytes, chunk: Chunk, owner: str) -> list[CustomData]:
    """An object's script simulation parameters (its ``Lsp`` chunk, ``CUserParameters``: a
    ``Par`` item with a count, then name, unit, value and properties each); the value's bytes."""
    base, _ = chunk_list(buf, chunk.start, chunk.end)
    out: list[CustomData] = []
    for c in base:
        if c.name != "Lsp":
            continue
        items, _ = chunk_list(buf, c.start, c.end)
        for item in items:
            if item.name != "Par":
                continue
            f = Fields(buf, item)
            for _ in range(max(0, f.i32())):
                name, _unit, value = f.string(), f.string(), f.string()
                f.i32()  # properties
                out.append(CustomData(owner, name, value.encode("utf-8").hex()))
    return out
