"""``sim.*`` functions on data: signals (one store for scripts, legacy and ZeroMQ clients),
custom data blocks (those the scene file carries, and written ones), packing tables into
buffers and back, bit operations, object parameters."""

from __future__ import annotations

import ctypes
import struct
from collections.abc import Callable
from typing import Any

from .context import Caller, SimError
from .objects import attach_dynamic, dummy_link_type
from .values import buffer, integer, number, table, text


# -- signals -------------------------------------------------------------------------------------
def _signal_set(kind: str, convert: Callable[[Any], Any]) -> Callable[..., Any]:
    def fn(c: Caller, name: Any, value: Any) -> int | None:
        c.signals[kind][text(name)] = convert(value)
        return c.done

    return fn


def _signal_get(kind: str) -> Callable[..., Any]:
    def fn(c: Caller, name: Any, *rest: Any) -> Any:
        value = c.signals[kind].get(text(name))
        if kind == "string" and value is not None:
            return bytes(value)
        return value

    return fn


def _signal_clear(kind: str) -> Callable[..., Any]:
    def fn(c: Caller, name: Any = None) -> int:
        table_ = c.signals[kind]
        if name is None or name in ("", b""):
            count = len(table_)
            table_.clear()
            return count
        return 1 if table_.pop(text(name), None) is not None else 0

    return fn


def _int32(v: Any) -> int:
    return ctypes.c_int32(integer(v, 2)).value


def _string(v: Any) -> bytes:
    if not isinstance(v, (str, bytes, bytearray)):
        raise SimError("argument 2: string expected")
    return buffer(v, 2)


SIGNALS: dict[str, Callable[..., Any]] = {}
for _kind, _names, _convert in (
    ("int", ("Int32", "Integer"), _int32),
    ("float", ("Float", "Double"), lambda v: number(v, 2)),
    ("string", ("String",), _string),
):
    for _n in _names:
        SIGNALS[f"set{_n}Signal"] = _signal_set(_kind, _convert)
        SIGNALS[f"get{_n}Signal"] = _signal_get(_kind)
        SIGNALS[f"clear{_n}Signal"] = _signal_clear(_kind)


def get_signal_name(c: Caller, index: Any, kind: Any) -> Any:
    names = list(c.signals[{0: "int", 1: "float", 2: "string"}.get(integer(kind, 2), "int")])
    i = integer(index, 1)
    return names[i] if 0 <= i < len(names) else None


# -- custom data blocks ----------------------------------------------------------------------------
def _owner(c: Caller, h: Any) -> int:
    hh = integer(h, 1)
    if hh in (-12, -13):  # sim.handle_scene, sim.handle_app
        return hh
    hh = c.handle(hh)
    c.entry(hh)
    return hh


def write_custom_data_block(c: Caller, h: Any, tag: Any, data: Any = None) -> int:
    key = (_owner(c, h), text(tag, 2))
    if data is None or data in (b"", ""):
        c.store.custom.pop(key, None)
    else:
        c.store.custom[key] = buffer(data, 3)
    return c.done


def read_custom_data_block(c: Caller, h: Any, tag: Any) -> bytes | None:
    return c.store.custom.get((_owner(c, h), text(tag, 2)))


def read_custom_data_block_tags(c: Caller, h: Any) -> list[str] | None:
    owner = _owner(c, h)
    tags = [tag for (o, tag) in c.store.custom if o == owner]
    return tags or None


def write_custom_table_data(c: Caller, h: Any, tag: Any, value: Any, *rest: Any) -> None:
    from .packing import pack

    write_custom_data_block(c, h, tag, pack(value) if value is not None else None)


def read_custom_table_data(c: Caller, h: Any, tag: Any, *rest: Any) -> Any:
    from .packing import unpack

    raw = read_custom_data_block(c, h, tag)
    return {} if raw is None else unpack(raw)


# -- packing -------------------------------------------------------------------------------------
def _pack(fmt: str) -> Callable[..., Any]:
    def fn(c: Caller, values: Any, start: Any = 0, count: Any = 0) -> bytes:
        v = table(values)[integer(start, 2, 0) :]
        n = integer(count, 3, 0)
        if n > 0:
            v = v[:n]
        if fmt in "fd":
            return struct.pack(f"<{len(v)}{fmt}", *[number(x) for x in v])
        return struct.pack(f"<{len(v)}{fmt}", *[int(x) for x in v])

    return fn


def _unpack(fmt: str, size: int) -> Callable[..., Any]:
    def fn(c: Caller, data: Any, start: Any = 0, count: Any = 0, offset: Any = 0) -> list[Any]:
        if data is None:
            raise SimError("argument 1: buffer expected, got nil")
        raw = buffer(data)[integer(offset, 4, 0) :]
        n = len(raw) // size
        values = list(struct.unpack(f"<{n}{fmt}", raw[: n * size]))[integer(start, 2, 0) :]
        k = integer(count, 3, 0)
        return values[:k] if k > 0 else values

    return fn


PACKING: dict[str, Callable[..., Any]] = {}
for _name, _fmt, _size in (
    ("FloatTable", "f", 4),
    ("DoubleTable", "d", 8),
    ("Int32Table", "i", 4),
    ("UInt32Table", "I", 4),
    ("UInt8Table", "B", 1),
    ("UInt16Table", "H", 2),
):
    PACKING["pack" + _name] = _pack(_fmt)
    PACKING["unpack" + _name] = _unpack(_fmt, _size)
PACKING["packFloats"] = PACKING["packFloatTable"]
PACKING["unpackFloats"] = PACKING["unpackFloatTable"]
PACKING["packInts"] = PACKING["packInt32Table"]
PACKING["unpackInts"] = PACKING["unpackInt32Table"]


def pack_table(c: Caller, value: Any, *rest: Any) -> bytes:
    from .packing import pack

    return pack(value)


def unpack_table(c: Caller, data: Any, *rest: Any) -> Any:
    from .packing import unpack

    try:
        return unpack(buffer(data))
    except ValueError as exc:
        raise SimError(str(exc)) from None


def transform_buffer(c: Caller, data: Any, in_fmt: Any, scale: Any, offset: Any, out_fmt: Any):
    """Only the identity conversions scenes use (float <-> double, uint8 scaled)."""
    fmts = {
        0: ("b", 1),
        1: ("B", 1),
        2: ("h", 2),
        3: ("H", 2),
        4: ("i", 4),
        5: ("I", 4),
        6: ("f", 4),
        7: ("d", 8),
    }
    fi, si = fmts.get(integer(in_fmt, 2), ("f", 4))
    fo, _ = fmts.get(integer(out_fmt, 5), ("f", 4))
    raw = buffer(data)
    vals = struct.unpack(f"<{len(raw) // si}{fi}", raw[: len(raw) // si * si])
    s, o = number(scale, 3), number(offset, 4)
    out = [v * s + o for v in vals]
    if fo not in "fd":
        out = [int(round(v)) for v in out]
    return struct.pack(f"<{len(out)}{fo}", *out)


# -- bits ----------------------------------------------------------------------------------------
BITS: dict[str, Callable[..., Any]] = {}
for _bits in (16, 32):
    _mask = (1 << _bits) - 1
    BITS[f"boolOr{_bits}"] = lambda c, a, b, m=_mask: (integer(a) | integer(b, 2)) & m
    BITS[f"boolAnd{_bits}"] = lambda c, a, b, m=_mask: (integer(a) & integer(b, 2)) & m
    BITS[f"boolXor{_bits}"] = lambda c, a, b, m=_mask: (integer(a) ^ integer(b, 2)) & m


# -- object parameters ---------------------------------------------------------------------------
#: sim.shapefloatparam_init_velocity_x..z, _a.._g (3000-3002, 3020-3022); mass 3005
INIT_VELOCITY = (3000, 3001, 3002, 3020, 3021, 3022)


def set_object_float_param(c: Caller, h: Any, pid: Any, value: Any) -> int:
    hh = c.handle(h)
    c.entry(hh)
    key = integer(pid, 2)
    c.store.object_params[(hh, key)] = number(value, 3)
    if key == 3005:  # shapefloatparam_mass
        _body_dynamics(c, hh, mass=number(value, 3))
    return c.done


def get_object_float_param(c: Caller, h: Any, pid: Any) -> Any:
    from .poses import get_object_velocity

    hh = c.handle(h)
    c.entry(hh)
    key = integer(pid, 2)
    if (hh, key) in c.store.object_params:
        value = c.store.object_params[(hh, key)]
    elif key in (11, 12, 13, 14):  # objfloatparam_abs_x/y/z_velocity, abs_rot_velocity
        lin, ang = get_object_velocity(c, hh)
        value = lin[key - 11] if key < 14 else sum(v * v for v in ang) ** 0.5
    elif key == 3005:
        value = _body_dynamics(c, hh)
    else:
        value = 0.0
    return float(value) if c.new_api else (1, float(value))


def set_object_int_param(c: Caller, h: Any, pid: Any, value: Any) -> int:
    hh = c.handle(h)
    c.entry(hh)
    key = integer(pid, 2)
    c.store.object_params[(hh, key)] = integer(value, 3)
    if key == 3003:  # shapeintparam_static: a part made static rides its parent, or is freed
        up = c.world.parent_of_object(hh)
        attach_dynamic(c, hh, -1 if up is None else up)
    return c.done


def get_object_int_param(c: Caller, h: Any, pid: Any) -> Any:
    hh = c.handle(h)
    c.entry(hh)
    key = integer(pid, 2)
    value = c.store.object_params.get((hh, key))
    if value is None:
        value = 0
        if key == 10000:  # dummyintparam_link_type
            value = dummy_link_type(c, hh)
        if key == 3003:  # shapeintparam_static
            ref = c.world.object_ref(hh)
            value = int(ref is None or ref.body < 0 or _body_dynamics(c, hh) == 0.0)
    return int(value) if c.new_api else (1, int(value))


def _body_dynamics(c: Caller, h: int, mass: float | None = None) -> float:
    from sims.quiet import pybullet as p

    ref = c.world.object_ref(h)
    if ref is None or ref.body < 0:
        return 0.0
    cid = c.world.client_id
    if mass is not None:
        p.changeDynamics(ref.body, ref.link, mass=mass, physicsClientId=cid)
    return float(p.getDynamicsInfo(ref.body, ref.link, physicsClientId=cid)[0])


def get_object_string_param(c: Caller, h: Any, pid: Any) -> Any:
    hh = c.handle(h)
    c.entry(hh)
    return c.store.object_params.get((hh, integer(pid, 2)), "")


def set_object_string_param(c: Caller, h: Any, pid: Any, value: Any) -> int:
    hh = c.handle(h)
    c.entry(hh)
    c.store.object_params[(hh, integer(pid, 2))] = value
    return c.done


def set_explicit_handling(c: Caller, h: Any, flags: Any) -> int:
    """Explicit handling of a sensor, IK group, collision or distance object: the default main
    script leaves it to scripts (``World.kinematics`` for IK groups, mech's)."""
    hh = integer(h, 1)
    on = bool(integer(flags, 2) & 1)
    c.store.explicit[("any", hh)] = on
    kin = getattr(c.world, "kinematics", None)
    if kin is not None:
        try:
            kin.set_explicit_handling(hh, on)
            return c.done
        except KeyError:
            pass
    return c.done


def get_explicit_handling(c: Caller, h: Any) -> int:
    kin = getattr(c.world, "kinematics", None)
    if kin is not None:
        try:
            return int(bool(kin.explicit_handling(integer(h, 1))))
        except KeyError:
            pass
    return int(c.store.explicit.get(("any", integer(h, 1)), False))


# -- tubes (V-REP 3.x: messages between scripts) ------------------------------------------------
def tube_open(c: Caller, header: Any, name: Any, buffer_size: Any = 0, *rest: Any) -> int:
    """The first two openers of a name are the two ends of one tube (CoppeliaSim's rule)."""
    key = ("tube", integer(header, 1), text(name, 2))
    ends = c.store.params.setdefault(key, [])
    if len(ends) >= 2:
        return -1
    h = c.store.new_handle("tube", 7_000_000)
    ends.append(h)
    c.store.params[("tube end", h)] = (key, [], integer(buffer_size, 3, 0))
    return h


def _tube(c: Caller, h: Any) -> tuple[Any, list[bytes], int]:
    got = c.store.params.get(("tube end", integer(h, 1)))
    if got is None:
        raise SimError(f"tube {h} does not exist")
    return got


def _other(c: Caller, h: int) -> Any:
    key, _, _ = _tube(c, h)
    ends = c.store.params.get(key, [])
    other = [e for e in ends if e != h]
    return c.store.params.get(("tube end", other[0])) if other else None


def tube_write(c: Caller, h: Any, data: Any) -> int:
    other = _other(c, integer(h, 1))
    if other is None:
        return -1
    _, queue, size = other
    queue.append(buffer(data, 2))
    if size > 0 and len(queue) > size:
        del queue[0]
    return c.done if c.new_api else 1


def tube_read(c: Caller, h: Any, blocking: Any = False) -> Any:
    _, queue, _ = _tube(c, h)
    return queue.pop(0) if queue else None


def tube_status(c: Caller, h: Any) -> tuple[int, int, int]:
    """(status: 0 not connected, 1 connected; packets to read; packets the other end holds)."""
    _, queue, _ = _tube(c, h)
    other = _other(c, integer(h, 1))
    return (1 if other is not None else 0), len(queue), len(other[1]) if other else 0


def tube_close(c: Caller, h: Any) -> int:
    hh = integer(h, 1)
    key, _, _ = _tube(c, hh)
    ends = c.store.params.get(key, [])
    if hh in ends:
        ends.remove(hh)
    c.store.params.pop(("tube end", hh), None)
    return 1
