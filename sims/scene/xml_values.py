"""Reading values out of ``.simscene.xml`` elements: text, numbers, switches, frames."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

from sims.scene.model import Pose
from sims.scene.rotations import euler_quat


def text(el: ET.Element | None, path: str, default: str | None = None) -> str | None:
    node = el.find(path) if el is not None else None
    if node is None or node.text is None:
        return default
    return node.text.strip()


def floats(el: ET.Element | None, path: str, n: int | None = None) -> tuple[float, ...] | None:
    raw = text(el, path)
    if raw is None:
        return None
    try:
        vals = tuple(float(x) for x in raw.split())
    except ValueError:
        raise ValueError(f"<{path}> holds {raw[:40]!r}, not numbers") from None
    if n is not None and len(vals) != n:
        raise ValueError(f"<{path}> holds {len(vals)} values, {n} expected")
    return vals


def number(el: ET.Element | None, path: str, default: float) -> float:
    vals = floats(el, path, 1)
    return vals[0] if vals else default


def flag(el: ET.Element | None, path: str, default: bool) -> bool:
    raw = text(el, path)
    if raw is None:
        return default
    if raw.lower() in ("true", "1"):
        return True
    if raw.lower() in ("false", "0"):
        return False
    raise ValueError(f"<{path}> holds {raw!r}, not true/false")


def frame(el: ET.Element | None) -> Pose:
    """A ``localFrame``: position and Euler angles in degrees, or a ``quaternion`` in
    CoppeliaSim's storage order (w, x, y, z)."""
    if el is None:
        return Pose()
    pos = floats(el, "position", 3) or (0.0, 0.0, 0.0)
    wxyz = floats(el, "quaternion", 4)
    if wxyz is not None:
        norm = math.sqrt(sum(v * v for v in wxyz)) or 1.0
        quat = tuple(v / norm for v in (*wxyz[1:], wxyz[0]))
    else:
        euler = floats(el, "euler", 3) or (0.0, 0.0, 0.0)
        quat = euler_quat(tuple(math.radians(a) for a in euler))
    return Pose(pos, quat)  # type: ignore[arg-type]
