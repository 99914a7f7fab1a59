"""The scene tree of one World: every object's handle, name, alias, parent and kind.

Handles are positions in this list plus one, so they are stable across ``reset()`` and the
remote API and Lua scripts can hold them. A scene file carries its tree; a bundled (hand-built)
scene's tree is derived here from the pybullet link chain.
"""

from __future__ import annotations

from dataclasses import dataclass

from sims.models.common import SceneModel
from sims.quiet import pybullet as p


@dataclass(frozen=True)
class TreeEntry:
    """One object of the World's scene tree. ``parent`` is the parent's handle (None at the
    top); ``kind`` is "shape", "joint", "dummy", "proximity_sensor", "vision_sensor"... as in
    sims.scene.model; ``alias`` is the 4.x alias ("" when the scene has none)."""

    handle: int
    name: str
    alias: str
    parent: int | None
    kind: str


def make_tree(m: SceneModel, client: int) -> list[TreeEntry]:
    """Handle = position + 1. Bundled scenes: objects, joints, then sensors, their parents
    following the pybullet link chain (a link's object under the joint that moves it)."""
    nodes = m.tree
    if nodes:
        index = {n.name: i + 1 for i, n in enumerate(nodes)}
        return [
            TreeEntry(i + 1, n.name, n.alias, index.get(n.parent or ""), n.kind)
            for i, n in enumerate(nodes)
        ]
    kinds = [(o.name, "shape") for o in m.objects] + [(j.name, "joint") for j in m.joints]
    kinds += [(s.name, "proximity_sensor") for s in m.sensors]
    index = {name: i + 1 for i, (name, _) in enumerate(kinds)}
    at_link = {(o.body, o.link): o.name for o in m.objects}
    joint_at = {(j.body, j.index): j.name for j in m.joints}

    def parent_link(body: int, link: int) -> int:
        return p.getJointInfo(body, link, physicsClientId=client)[16]

    def object_at(body: int, link: int) -> str | None:
        while (body, link) not in at_link and link >= 0:
            link = parent_link(body, link)
        return at_link.get((body, link))

    parents: dict[str, str | None] = {}
    for o in m.objects:
        if o.link < 0:
            parents[o.name] = None
        else:
            parents[o.name] = joint_at.get((o.body, o.link)) or object_at(
                o.body, parent_link(o.body, o.link)
            )
    for j in m.joints:
        parents[j.name] = object_at(j.body, parent_link(j.body, j.index))
    for sensor in m.sensors:
        parents[sensor.name] = object_at(sensor.body, sensor.link)
    return [
        TreeEntry(index[name], name, "", index.get(parents[name] or ""), kind)
        for name, kind in kinds
    ]
