"""Arguments of ``sim.*`` functions as plain values: what each edge (Lua, CBOR) may hand in.

A string arrives as ``str`` (ZeroMQ) or ``bytes`` (Lua strings, which are byte strings); a
table as a list or a dict (a Lua table with keys 1..n is a list); nil as None.
"""

from __future__ import annotations

import math
from typing import Any

from .context import SimError


def text(value: Any, position: int = 1) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, (bytes, bytearray)):
        return bytes(value).decode("utf-8", "replace")
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return str(value)  # Lua coerces numbers to strings
    raise SimError(f"argument {position}: string expected, got {value!r}")


def buffer(value: Any, position: int = 1) -> bytes:
    if isinstance(value, (bytes, bytearray)):
        return bytes(value)
    if isinstance(value, str):
        return value.encode("utf-8")
    raise SimError(f"argument {position}: buffer expected, got {value!r}")


def number(value: Any, position: int = 1) -> float:
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    raise SimError(f"argument {position}: number expected, got {value!r}")


def finite(value: Any, position: int = 1) -> float:
    v = number(value, position)
    if not math.isfinite(v):
        raise SimError(f"argument {position}: finite number expected, got {v!r}")
    return v


def integer(value: Any, position: int = 1, default: int | None = None) -> int:
    if value is None and default is not None:
        return default
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, int):
        return value
    if isinstance(value, float) and value.is_integer():
        return int(value)
    raise SimError(f"argument {position}: integer expected, got {value!r}")


def flag(value: Any, default: bool = False) -> bool:
    if value is None:
        return default
    if isinstance(value, (int, float)):
        return value != 0
    return bool(value)


def numbers(value: Any) -> list[float]:
    """A table of numbers (None: empty); non-numbers are left out."""
    if value is None:
        return []
    if isinstance(value, dict):
        value = [value[k] for k in sorted(k for k in value if isinstance(k, int))]
    if not isinstance(value, (list, tuple)):
        return []
    return [float(v) for v in value if isinstance(v, (int, float)) and not isinstance(v, bool)]


def vector(value: Any, n: int, position: int = 1) -> list[float]:
    v = numbers(value)
    if len(v) < n:
        raise SimError(f"argument {position}: table of {n} numbers expected")
    return v[:n]


def table(value: Any) -> list[Any]:
    if value is None:
        return []
    if isinstance(value, dict):
        return [value[k] for k in sorted(k for k in value if isinstance(k, int))]
    if isinstance(value, (list, tuple)):
        return list(value)
    return [value]


def options(value: Any) -> dict[str, Any]:
    """A table of named options (``{'index': 1, 'noError': True}``); anything else: empty."""
    return value if isinstance(value, dict) else {}
