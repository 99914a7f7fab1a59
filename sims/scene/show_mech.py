"""The mechanisms part of ``sitegen scene show``: the physics settings, IK groups, paths and loop
closures of a scene, with what sitegen makes of each (how a loop is closed, which joints an IK
element moves, a path's length), and the report of a scene built by hand in Python.
"""

from __future__ import annotations

import json
import math
import sys
from typing import Any

from sims.scene.model import Scene
from sims.scene.model_mech import IK_ALPHA_BETA, IK_GAMMA, IK_X, IK_Y, IK_Z

CONSTRAINT_NAMES = (
    (IK_X, "x"),
    (IK_Y, "y"),
    (IK_Z, "z"),
    (IK_ALPHA_BETA, "alpha-beta"),
    (IK_GAMMA, "gamma"),
)


def _name(scene: Scene, handle: int | None) -> str:
    if handle is None:
        return "world"
    o = scene.by_handle().get(handle)
    return o.name if o is not None else f"[{handle}]"


def _chain(scene: Scene, tip: int, base: int | None) -> list[str]:
    """The joints between an IK element's base and tip, base first, with their modes."""
    table = scene.by_handle()
    out = []
    cur = table.get(tip)
    while cur is not None and cur.handle != base:
        if cur.kind == "joint" and cur.joint is not None:
            hybrid = " hybrid" if cur.joint.hybrid else ""
            out.append(f"{cur.name} ({cur.joint.mode}{hybrid})")
        cur = table.get(cur.parent) if cur.parent is not None else None
    return list(reversed(out))


def mechanisms(scene: Scene) -> dict[str, Any]:
    """The JSON form: ``physics``, ``ik_groups``, ``paths``, ``loops``."""
    from sims.path_objects import Curve
    from sims.scene.loops import describe

    table = scene.by_handle()
    groups = []
    for g in scene.ik_groups:
        elements = []
        for e in g.elements:
            tip = table.get(e.tip)
            target = tip.dummy.linked_to if tip is not None and tip.dummy else None
            elements.append(
                {
                    "tip": _name(scene, e.tip),
                    "target": _name(scene, target) if target is not None else None,
                    "base": _name(scene, e.base),
                    "constraints": [n for bit, n in CONSTRAINT_NAMES if e.constraints & bit],
                    "precision": [round(e.precision[0], 6), round(math.degrees(e.precision[1]), 4)],
                    "weights": [round(w, 4) for w in e.weights],
                    "enabled": e.enabled,
                    "joints": _chain(scene, e.tip, e.base),
                }
            )
        groups.append(
            {
                "name": g.name,
                "method": g.method,
                "damping": round(g.damping, 6),
                "iterations": g.iterations,
                "explicit": g.explicit,
                "enabled": g.enabled,
                "elements": elements,
            }
        )
    paths = []
    for o in scene.objects:
        if o.path is None:
            continue
        followers = [k for k in scene.children(o.handle) if k.dummy and k.dummy.follows_path]
        paths.append(
            {
                "name": o.name,
                "closed": o.path.closed,
                "control_points": len(o.path.points),
                "length": round(Curve.of(o.path).length, 6),
                "position": round(o.path.position, 6),
                "nominal_velocity": round(o.path.nominal_velocity, 6),
                "followers": len(followers),
            }
        )
    ph = scene.physics
    return {
        "physics": {
            "engine": ph.engine,
            "step": round(ph.step, 6),
            "iterations": ph.iterations,
            "enabled": ph.enabled,
        },
        "ik_groups": groups,
        "paths": paths,
        "loops": describe(scene),
    }


def mechanism_lines(scene: Scene) -> list[str]:
    """The text form (after the scripts)."""
    m = mechanisms(scene)
    ph = m["physics"]
    lines = [
        "",
        f"Physics: {ph['engine']}, step {ph['step'] * 1000:g} ms, "
        f"{ph['iterations']} solver iterations{'' if ph['enabled'] else ', dynamics off'}",
    ]
    if m["ik_groups"]:
        lines.append("IK groups:")
        for g in m["ik_groups"]:
            flags = ", explicit handling" if g["explicit"] else ""
            flags += "" if g["enabled"] else ", disabled"
            lines.append(
                f"  {g['name']}: {g['method'].replace('_', ' ')}, damping {g['damping']:g}, "
                f"{g['iterations']} iterations{flags}"
            )
            for e in g["elements"]:
                lines.append(
                    f"    {e['tip']} -> {e['target']} from {e['base']}: "
                    f"{' '.join(e['constraints'])}; precision {e['precision'][0]:g} m, "
                    f"{e['precision'][1]:g}°; joints {', '.join(e['joints']) or 'none'}"
                )
    if m["paths"]:
        lines.append("Paths:")
        for pth in m["paths"]:
            lines.append(
                f"  {pth['name']}: {'closed' if pth['closed'] else 'open'}, "
                f"{pth['control_points']} control points, length {pth['length']:.4g} m, "
                f"position {pth['position']:g} m, {pth['followers']} dummies follow it"
            )
    if m["loops"]:
        lines.append("Loop closures:")
        for loop in m["loops"]:
            a, b = loop["dummies"]
            lines.append(f"  {a} <-> {b}: {loop['built_as']}")
    return lines


def hand_built_report(name: str, args: Any) -> int:
    """A bundled scene built in Python (no file): its object tree from a World."""
    from sims.world import World

    with World(name) as world:
        tree = world.tree()
    if getattr(args, "json", False):
        doc = {
            "source": name,
            "format": "hand-built",
            "objects": [
                {"handle": e.handle, "name": e.name, "kind": e.kind, "parent": e.parent}
                for e in tree
            ],
        }
        sys.stdout.write(json.dumps(doc, indent=1, sort_keys=True) + "\n")
        return 0
    lines = [f"{name}: a bundled scene built in Python (sims/models/), {len(tree)} objects", ""]
    kids: dict[int | None, list[Any]] = {}
    for e in tree:
        kids.setdefault(e.parent, []).append(e)

    def walk(parent: int | None, depth: int) -> None:
        for e in kids.get(parent, []):
            lines.append(f"{'  ' * depth}{e.name} [{e.handle}] {e.kind}")
            walk(e.handle, depth + 1)

    walk(None, 0)
    sys.stdout.write("\n".join(lines) + "\n")
    return 0
