"""``sim.*`` functions on data: signals (shared with the remote API), custom data blocks, packing,
bit operations."""

from __future__ import annotations

import struct
from collections.abc import Callable
from typing import Any

from .api_core import REGISTRY, Context, api
from .runtime import text, to_py


# -- signals and custom data ---------------------------------------------------------------------
def _signal_set(kind: str, convert: Callable[[Any], Any]):
    def fn(c: Context, name: Any, value: Any) -> Any:
        c.host.signals[kind][text(name)] = convert(value)
        return 1

    return fn


def _signal_get(kind: str, convert: Callable[[Any], Any]):
    def fn(c: Context, name: Any, *rest: Any) -> Any:
        table = c.host.signals[kind]
        n = text(name)
        return convert(table[n]) if n in table else None

    return fn


def _signal_clear(kind: str):
    def fn(c: Context, name: Any = None) -> Any:
        table = c.host.signals[kind]
        if name is None:
            count = len(table)
            table.clear()
            return count
        return 1 if table.pop(text(name), None) is not None else 0

    return fn


for _kind, _new, _set, _get in (
    ("int", "Int32Signal", lambda v: int(v), lambda v: int(v)),
    ("float", "FloatSignal", lambda v: float(v), lambda v: float(v)),
    ("string", "StringSignal", lambda v: bytes(v), lambda v: bytes(v)),
):
    REGISTRY["set" + _new] = _signal_set(_kind, _set)
    REGISTRY["get" + _new] = _signal_get(_kind, _get)
    REGISTRY["clear" + _new] = _signal_clear(_kind)
REGISTRY["setIntegerSignal"] = REGISTRY["setInt32Signal"]
REGISTRY["getIntegerSignal"] = REGISTRY["getInt32Signal"]
REGISTRY["clearIntegerSignal"] = REGISTRY["clearInt32Signal"]


@api("writeCustomDataBlock")
def write_custom_data_block(c: Context, h: Any, tag: Any, data: Any) -> Any:
    key = (c.handle(h), text(tag))
    if data is None or data == b"":
        c.host.custom.pop(key, None)
    else:
        c.host.custom[key] = bytes(data)
    return 1


@api("readCustomDataBlock")
def read_custom_data_block(c: Context, h: Any, tag: Any) -> Any:
    return c.host.custom.get((c.handle(h), text(tag)))


# -- packing -----------------------------------------------------------------------------------
def _pack(fmt: str):
    def fn(c: Context, values: Any, start: Any = 0, count: Any = 0) -> Any:
        v = to_py(values) or []
        v = v[int(start) :]
        if int(count) > 0:
            v = v[: int(count)]
        return struct.pack(f"<{len(v)}{fmt}", *v)

    return fn


def _unpack(fmt: str, size: int):
    def fn(c: Context, data: Any, start: Any = 0, count: Any = 0, offset: Any = 0) -> Any:
        raw = bytes(data)[int(offset or 0) :]
        n = len(raw) // size
        values = list(struct.unpack(f"<{n}{fmt}", raw[: n * size]))[int(start) :]
        return values[: int(count)] if int(count) > 0 else values

    return fn


for _name, _fmt, _size in (
    ("FloatTable", "f", 4),
    ("DoubleTable", "d", 8),
    ("Int32Table", "i", 4),
    ("UInt32Table", "I", 4),
    ("UInt8Table", "B", 1),
    ("UInt16Table", "H", 2),
):
    REGISTRY["pack" + _name] = _pack(_fmt)
    REGISTRY["unpack" + _name] = _unpack(_fmt, _size)
REGISTRY["packFloats"] = REGISTRY["packFloatTable"]
REGISTRY["unpackFloats"] = REGISTRY["unpackFloatTable"]
REGISTRY["packInts"] = REGISTRY["packInt32Table"]
REGISTRY["unpackInts"] = REGISTRY["unpackInt32Table"]


@api("packTable")
def pack_table(c: Context, table: Any, *rest: Any) -> Any:
    from .packing import pack

    return pack(to_py(table))


@api("unpackTable")
def unpack_table(c: Context, data: Any) -> Any:
    from .packing import unpack

    try:
        return unpack(bytes(data))
    except ValueError as exc:
        return c.state.fail(str(exc))


# -- bits --------------------------------------------------------------------------------------
for _bits in (16, 32):
    _mask = (1 << _bits) - 1
    REGISTRY[f"boolOr{_bits}"] = lambda c, a, b, m=_mask: (int(a) | int(b)) & m
    REGISTRY[f"boolAnd{_bits}"] = lambda c, a, b, m=_mask: (int(a) & int(b)) & m
    REGISTRY[f"boolXor{_bits}"] = lambda c, a, b, m=_mask: (int(a) ^ int(b)) & m


@api("buildIdentityMatrix")
def build_identity_matrix(c: Context) -> Any:
    return [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0]


@api("getNameSuffix")
def get_name_suffix(c: Context, name: Any = None) -> Any:
    if name is None:
        return (-1, "")
    n = text(name)
    base, sep, suffix = n.rpartition("#")
    if sep and suffix.isdigit():
        return (int(suffix), base)
    return (-1, n)
