"""Loop closures: two linked dummies that the physics holds together (CoppeliaSim's dynamics
overlap constraint), as in four-bar linkages, a Jansen leg or the RG2 gripper.

What CoppeliaSim does (its Bullet plugin, ``simDyn``: ``CConstraintDyn``): the two dummies are
held at the same position *and* orientation (a six-axis lock). When one dummy hangs from a
joint with no body of its own in between (joint → dummyA ⇄ dummyB ← body B, the way loops are
closed), the joint itself joins its parent body and body B: the loop's last pivot.

pybullet builds each body as a tree (a multibody), so a loop is closed with constraints:

- a *closing joint* (revolute or spherical, not motorised, with nothing but dummies below it)
  gets no link of its own: it becomes point-to-point constraints between its parent link and
  body B, two on a revolute joint's axis, one at a spherical joint's centre. Its position is
  read from the relative pose of the two links (``JointRef.closure``). Building it as a link
  (a light virtual body welded to body B) puts a mass ratio of up to 10^4 into the loop, which
  the iterative solver cannot hold: the loop drifted open by decimetres;
- any other linked pair is welded (``JOINT_FIXED``) with the constraint's frame at the joint
  above the dummy or, without one, at the first link's centre of mass: scenes exported from
  SolveSpace put every dummy at the world origin, a metre from the links, where a weld's small
  angular error shows as a large gap.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from sims.models.common import Closure, JointRef
from sims.quiet import pybullet as p
from sims.scene.bodies import Created, Tf, inv, mul
from sims.scene.model import Scene, SceneObject

_Planner = Any  # sims.scene.build._Planner (build imports this module, not the other way)
MakeRef = Callable[[SceneObject, int, int], JointRef]

AXIS_HALF = 0.05  # m: the two points that make a closing revolute joint's axis, either side
CLOSING_KINDS = ("revolute", "spherical")
MAX_FORCE = 1e4


@dataclass(frozen=True)
class ClosingJoint:
    """A joint that closes a loop: ``dummy`` hangs from it and is linked to ``partner``."""

    joint: SceneObject
    dummy: SceneObject
    partner: SceneObject
    below: tuple[int, ...]  # handles of everything under the joint (dummies, sensors...)


def linked_pairs(scene: Scene) -> list[tuple[SceneObject, SceneObject]]:
    """Each pair of dummies linked with a dynamics link type, once, in file order."""
    table = scene.by_handle()
    done: set[frozenset[int]] = set()
    out = []
    for o in scene.objects:
        data = o.dummy
        if data is None or data.linked_to is None or data.linked_to not in table:
            continue
        if not data.link_type.startswith("dynamics") or data.linked_to == o.handle:
            continue
        pair = frozenset((o.handle, data.linked_to))
        if pair not in done:
            done.add(pair)
            out.append((o, table[data.linked_to]))
    return out


def _motorised(j: SceneObject) -> bool:
    d = j.joint
    return d is not None and d.mode in ("position", "velocity") and d.motor_enabled


def closing_joints(
    scene: Scene, kids: dict[int | None, list[SceneObject]]
) -> dict[int, ClosingJoint]:
    """The joints that close loops, by handle (see the module docstring)."""
    table = scene.by_handle()
    out: dict[int, ClosingJoint] = {}
    for a, b in linked_pairs(scene):
        for dummy, partner in ((a, b), (b, a)):
            joint = table.get(dummy.parent) if dummy.parent is not None else None
            while joint is not None and joint.kind == "dummy":
                joint = table.get(joint.parent) if joint.parent is not None else None
            if joint is None or joint.kind != "joint" or joint.joint is None:
                continue
            if joint.joint.kind not in CLOSING_KINDS or _motorised(joint) or joint.handle in out:
                continue
            below = _subtree(joint.handle, kids)
            if partner.handle in below or any(
                table[h].kind in ("shape", "joint", "force_sensor") for h in below
            ):
                continue
            out[joint.handle] = ClosingJoint(joint, dummy, partner, tuple(sorted(below)))
            break
    return out


def _subtree(handle: int, kids: dict[int | None, list[SceneObject]]) -> set[int]:
    out: set[int] = set()
    stack = [handle]
    while stack:
        for child in kids.get(stack.pop(), []):
            if child.handle not in out:
                out.add(child.handle)
                stack.append(child.handle)
    return out


def _com(client: int, made: Created | None, planned: int, frame: Tf) -> tuple[int, int, Tf]:
    """(body id, link index, world frame of the link's centre of mass); the world: (-1, -1)."""
    if made is None:
        return -1, -1, ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
    row = made.rows[planned]
    info = p.getDynamicsInfo(made.uid, row, physicsClientId=client)
    return made.uid, row, mul(frame, (info[3], info[4]))


def _end(client: int, plan: _Planner, created: list[Created], at: tuple[int, int] | None):
    if at is None:
        return _com(client, None, 0, ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)))
    body, planned = at
    return _com(client, created[body], planned, plan.bodies[body].links[planned].frame)


def _point(client: int, a, b, world_point) -> int:
    """A point-to-point constraint between two links (or a link and the world) at a point."""
    ua, la, ca = a
    ub, lb, cb = b
    pa = mul(inv(ca), (world_point, (0.0, 0.0, 0.0, 1.0)))[0]
    pb = mul(inv(cb), (world_point, (0.0, 0.0, 0.0, 1.0)))[0]
    if ua < 0:  # the world must be the child of a constraint
        (ua, la, pa), (ub, lb, pb) = (ub, lb, pb), (ua, la, pa)
    cid = p.createConstraint(
        ua, la, ub, lb, p.JOINT_POINT2POINT, (0, 0, 0), pa, pb, physicsClientId=client
    )
    p.changeConstraint(cid, maxForce=MAX_FORCE, erp=0.8, physicsClientId=client)
    return cid


def _weld(client: int, a, b, pivot: Tf) -> int:
    ua, la, ca = a
    ub, lb, cb = b
    fa, fb = mul(inv(ca), pivot), mul(inv(cb), pivot)
    if ua < 0:
        (ua, la, fa), (ub, lb, fb) = (ub, lb, fb), (ua, la, fa)
    cid = p.createConstraint(
        ua, la, ub, lb, p.JOINT_FIXED, (0, 0, 0), fa[0], fb[0], fa[1], fb[1],
        physicsClientId=client,
    )  # fmt: skip
    p.changeConstraint(cid, maxForce=MAX_FORCE, erp=0.8, physicsClientId=client)
    return cid


def close(
    client: int, scene: Scene, plan: _Planner, created: list[Created], make_ref: MakeRef
) -> dict[int, JointRef]:
    """Create the scene's loop-closure constraints; returns the closing joints' records
    (``make_ref`` is the builder's JointRef for a joint object on a body's link)."""
    refs: dict[int, JointRef] = {}
    closed: set[frozenset[int]] = set()
    for h, cj in plan.closing.items():
        parent_at = plan.closing_parent.get(h)
        partner_at = plan.where.get(cj.partner.handle)
        a = _end(client, plan, created, parent_at)
        b = _end(client, plan, created, partner_at)
        if a[0] < 0 and b[0] < 0:
            continue
        closed.add(frozenset((cj.dummy.handle, cj.partner.handle)))
        full = plan.full[h]
        if cj.joint.joint is not None and cj.joint.joint.kind == "revolute":
            for s in (-AXIS_HALF, AXIS_HALF):
                _point(client, a, b, mul(full, ((0.0, 0.0, s), (0.0, 0.0, 0.0, 1.0)))[0])
        else:
            _point(client, a, b, full[0])
        refs[h] = _closure_ref(cj.joint, plan, parent_at, partner_at, a, b, make_ref)
    for d1, d2 in linked_pairs(scene):
        if frozenset((d1.handle, d2.handle)) in closed:
            continue
        at1, at2 = plan.where.get(d1.handle), plan.where.get(d2.handle)
        if at1 == at2:
            continue  # both ride on the same link (or both are fixed in the world)
        a = _end(client, plan, created, at1)
        b = _end(client, plan, created, at2)
        _weld(client, a, b, _pivot(plan, d1, a, b))
    return refs


def _pivot(plan: _Planner, dummy: SceneObject, a, b) -> Tf:
    """Where a weld's frame goes: at the joint the dummy hangs from, else at a link's centre of
    mass (the moving one), with the world's orientation."""
    cur = plan.table.get(dummy.parent) if dummy.parent is not None else None
    while cur is not None and cur.kind == "dummy":
        cur = plan.table.get(cur.parent) if cur.parent is not None else None
    if cur is not None and cur.kind in ("joint", "force_sensor"):
        return plan.full[cur.handle][0], (0.0, 0.0, 0.0, 1.0)
    com = a[2] if a[0] >= 0 else b[2]
    return com[0], (0.0, 0.0, 0.0, 1.0)


def _closure_ref(
    joint: SceneObject, plan: _Planner, parent_at, partner_at, a, b, make_ref: MakeRef
) -> JointRef:
    base, full = plan.base[joint.handle], plan.full[joint.handle]
    parent_frame = _link_frame(plan, parent_at)
    child_frame = _link_frame(plan, partner_at)
    closure = Closure(
        child_body=b[0],
        child_link=b[1],
        parent_frame=mul(inv(parent_frame), base),
        child_frame=mul(inv(child_frame), full),
    )
    ref = make_ref(joint, a[0], a[1])
    mode = "spring" if ref.mode == "spring" else "free"
    return dataclasses.replace(ref, closure=closure, mode=mode)


def _link_frame(plan: _Planner, at: tuple[int, int] | None) -> Tf:
    if at is None:
        return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)
    return plan.bodies[at[0]].links[at[1]].frame


def describe(scene: Scene) -> list[dict]:
    """How each loop closure of the scene is built (for ``sitegen scene show``)."""
    kids: dict[int | None, list[SceneObject]] = {}
    table = scene.by_handle()
    for o in scene.objects:
        kids.setdefault(o.parent if o.parent in table else None, []).append(o)
    closing = closing_joints(scene, kids)
    by_pair = {frozenset((c.dummy.handle, c.partner.handle)): c for c in closing.values()}
    out = []
    for a, b in linked_pairs(scene):
        cj = by_pair.get(frozenset((a.handle, b.handle)))
        item = {"dummies": [a.name, b.name], "link_type": a.dummy.link_type if a.dummy else ""}
        if cj is not None:
            kind = cj.joint.joint.kind if cj.joint.joint else "revolute"
            points = "two point constraints on its axis" if kind == "revolute" else "a ball joint"
            item["built_as"] = f"closing joint {cj.joint.name} ({kind}): {points}"
            item["joint"] = cj.joint.name
        elif not (_moves(a, table) or _moves(b, table)):
            item["built_as"] = "both fixed in the world: nothing to hold"
        else:
            item["built_as"] = "weld (the two dummies' frames held together)"
        out.append(item)
    return out


def _moves(o: SceneObject, table: dict[int, SceneObject]) -> bool:
    """Something above it moves under physics (a joint or a dynamic shape)."""
    cur = table.get(o.parent) if o.parent is not None else None
    while cur is not None:
        if cur.kind in ("joint", "force_sensor"):
            return True
        if cur.shape is not None and not cur.shape.dynamics.static:
            return True
        cur = table.get(cur.parent) if cur.parent is not None else None
    return False
