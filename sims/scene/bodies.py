"""One planned body (a base and its joint links) created as a pybullet multibody.

Physics and looks are split for speed. A link collides with one compound of the primitive parts
riding on it (pybullet's shape arrays); a mesh part, which cannot join a compound, sits on a
massless fixed child link instead (contacts on it push the link it is fixed to, as one compound
would). What a link *looks* like is drawn by visual-only bodies that collide with nothing and are
created when the scene is first drawn and moved onto their link only when a frame is rendered
(``World.sync_visuals``), so the dozens of meshes of a detailed robot cost nothing per physics
step, nor anything at all in a run that draws nothing. Static shapes that ride on a moving link and
do not respond (CoppeliaSim's usual "visual" meshes) are looks only.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from sims.models.common import MAX_COMPOUND
from sims.quiet import pybullet as p
from sims.quiet import quiet_fd
from sims.scene import shapes as S
from sims.scene.model import SceneObject
from sims.scene.textures import texture_file

VIRTUAL_MASS, VIRTUAL_INERTIA = 0.1, 1e-4  # a joint's link when no dynamic shape hangs on it
DEFAULT_FRICTION = 0.71  # CoppeliaSim's default Bullet friction for a shape
STATIC = 8  # collision group of fixed geometry (fixed never collides with fixed)
IDENTITY_TF = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
Tf = tuple[tuple[float, float, float], tuple[float, float, float, float]]
JOINT_TYPES = {
    "revolute": p.JOINT_REVOLUTE,
    "prismatic": p.JOINT_PRISMATIC,
    "spherical": p.JOINT_SPHERICAL,
}
PRIMITIVES = {p.GEOM_BOX, p.GEOM_SPHERE, p.GEOM_CYLINDER}


def mul(a: Tf, b: Tf) -> Tf:
    return p.multiplyTransforms(a[0], a[1], b[0], b[1])  # type: ignore[return-value]


def inv(a: Tf) -> Tf:
    return p.invertTransform(a[0], a[1])  # type: ignore[return-value]


@dataclass
class Link:
    """One planned link (links[0] of a body is its base)."""

    frame: Tf  # world frame in the saved pose
    parent: int = 0  # index of the parent in the body's link list
    joint: SceneObject | None = None  # the joint or force sensor that makes it (None: base)
    joint_base: Tf = IDENTITY_TF  # the joint's own frame (before its motion), world
    carrier: SceneObject | None = None  # the dynamic shape whose mass it has
    carrier_frame: Tf = IDENTITY_TF  # that shape's world frame
    parts: list[tuple[S.Part, SceneObject]] = field(default_factory=list)


@dataclass
class Body:
    links: list[Link]
    fixed: bool


@dataclass(frozen=True)
class Visual:
    """A visual-only body drawn on a moving link: pose = link frame x ``offset``."""

    uid: int
    body: int
    link: int
    offset: Tf


@dataclass
class Created:
    uid: int
    rows: dict[int, int]  # planned link index -> pybullet link index (-1: base)
    parts: list[tuple[int, int, S.Part, SceneObject]]  # colliding: (row, planned, part, shape)
    looks: list[tuple] = field(default_factory=list)  # (uid, row, moving, frame, part) to draw


def _mass(link: Link, fixed_base: bool) -> tuple[float, tuple[float, ...], Tf]:
    if fixed_base:
        return 0.0, (0.0, 0.0, 0.0), IDENTITY_TF
    shape = link.carrier.shape if link.carrier is not None else None
    if shape is None:
        return VIRTUAL_MASS, (VIRTUAL_INERTIA,) * 3, IDENTITY_TF
    d = shape.dynamics
    inertia_tf = (d.inertia_frame.position, d.inertia_frame.quaternion)
    frame = mul(mul(inv(link.frame), link.carrier_frame), inertia_tf)
    return max(d.mass, 1e-3), tuple(max(v, 1e-9) for v in d.inertia), frame


def _collides(part: S.Part, fixed: bool) -> bool:
    """Fixed geometry always collides (cheap); on a moving link a static non-respondable
    shape is only looks."""
    return fixed or part.respondable or not part.static


def compound_shape(c: int, parts: list[S.Part]) -> int:
    """One collision shape for the primitive parts (the first MAX_COMPOUND), or -1."""
    return _compound(c, parts)[0]


def _compound(c: int, parts: list[S.Part]) -> tuple[int, list[S.Part]]:
    """One collision shape for the primitive parts; returns it and the parts left over (meshes,
    and primitives past the first MAX_COMPOUND: pybullet silently keeps only that many shapes
    of an array, which left the conveyor's belt box out of its collision shape)."""
    prims, rest = [], []
    for part in parts:
        geometry = S.geometry(part)
        if geometry is not None and geometry[0]["shapeType"] in PRIMITIVES:
            prims.append((part, geometry[0]))
        elif geometry is not None:
            rest.append(part)
    if len(prims) > MAX_COMPOUND:  # respondable ones first: they matter most in the compound
        prims.sort(key=lambda item: not item[0].respondable)
        rest = [part for part, _ in prims[MAX_COMPOUND:]] + rest
        prims = prims[:MAX_COMPOUND]
    if not prims:
        return -1, rest
    col = p.createCollisionShapeArray(
        [g["shapeType"] for _, g in prims],
        radii=[g.get("radius", 0.0) for _, g in prims],
        halfExtents=[g.get("halfExtents", (0.0, 0.0, 0.0)) for _, g in prims],
        lengths=[g.get("height", 0.0) for _, g in prims],
        collisionFramePositions=[pt.pose.position for pt, _ in prims],
        collisionFrameOrientations=[pt.pose.quaternion for pt, _ in prims],
        physicsClientId=c,
    )
    return col, rest


def _apart(parts: list[tuple[S.Part, SceneObject]]) -> set[int]:
    """On a fixed body, the respondable parts of every shape but the first each get a link of
    their own, so that one of them can be switched off or set moving alone (a conveyor's belt:
    World.set_initial_velocity)."""
    owners = [o.handle for pt, o in parts if pt.respondable]
    return {id(pt) for pt, o in parts if pt.respondable and owners and o.handle != owners[0]}


def create_body(client: int, body: Body) -> Created:
    c = client
    links = body.links
    rows: dict[int, int] = {0: -1}
    spec: list[dict] = []
    own_col: dict[int, int] = {}
    extra: list[tuple[int, S.Part, SceneObject, int]] = []  # (planned, part, owner, shape id)
    colliding: dict[int, list[tuple[S.Part, SceneObject]]] = {}
    in_compound: dict[int, set[int]] = {}
    for i, link in enumerate(links):
        fixed = body.fixed and i == 0
        mine = [(pt, o) for pt, o in link.parts if _collides(pt, fixed)]
        colliding[i] = mine
        apart = _apart(mine) if fixed else set()
        col, rest = _compound(c, [pt for pt, _ in mine if id(pt) not in apart])
        rest = [pt for pt, _ in mine if id(pt) in apart] + rest
        own_col[i] = col
        in_compound[i] = {id(pt) for pt, _ in mine} - {id(pt) for pt in rest}
        owners = {id(pt): o for pt, o in mine}
        for part in rest:
            shape_id = S.create_collision(c, part, fixed)
            if shape_id >= 0:
                extra.append((i, part, owners[id(part)], shape_id))
    for i, link in enumerate(links[1:], start=1):
        rel = mul(inv(links[link.parent].frame), link.joint_base)
        mass, inertia, inertial = _mass(link, False)
        kind = link.joint.joint.kind if link.joint is not None and link.joint.joint else ""
        rows[i] = len(spec)
        spec.append(
            {
                "mass": mass,
                "col": own_col[i],
                "tf": rel,
                "inertial": inertial,
                "parent": rows[link.parent] + 1,
                "type": JOINT_TYPES.get(kind, p.JOINT_FIXED),
                "inertia": inertia,
            }
        )
    parts: list[tuple[int, int, S.Part, SceneObject]] = []
    for i, mine in colliding.items():
        if own_col[i] >= 0:
            parts += [(rows[i], i, pt, o) for pt, o in mine if id(pt) in in_compound[i]]
    for i, part, owner, shape_id in extra:
        parts.append((len(spec), i, part, owner))
        spec.append(
            {
                "mass": 0.0,
                "col": shape_id,
                "tf": IDENTITY_TF,
                "inertial": IDENTITY_TF,
                "parent": rows[i] + 1,
                "type": p.JOINT_FIXED,
                "inertia": None,
            }
        )
    order = _preorder(spec)
    new_row = {old: new for new, old in enumerate(order)}
    spec = [
        dict(
            spec[old],
            parent=(0 if spec[old]["parent"] == 0 else new_row[spec[old]["parent"] - 1] + 1),
        )
        for old in order
    ]
    rows = {i: (-1 if r < 0 else new_row[r]) for i, r in rows.items()}
    parts = [(new_row[r] if r >= 0 else r, i, pt, o) for r, i, pt, o in parts]
    base_mass, base_inertia, base_inertial = _mass(links[0], body.fixed)
    # The scene's look is drawn by separate visual bodies (create_visuals), so a physics link
    # must draw nothing. pybullet's EGL plugin draws a link that has no visual shape from its
    # collision shape, in its own palette (green, yellow, red: the hidden respondable shapes of
    # a CoppeliaSim model would show, and the floor's hidden cuboid z-fights with its visible
    # tiles); hence a sub-pixel, transparent visual shape on every link. It also says on stdout,
    # once per mesh, that it could not draw a mesh given as vertices: kept off the CLI.
    hidden = p.createVisualShape(
        p.GEOM_SPHERE, radius=1e-6, rgbaColor=(0.0, 0.0, 0.0, 0.0), physicsClientId=c
    )
    with quiet_fd(1):
        uid = p.createMultiBody(
            baseMass=base_mass,
            baseCollisionShapeIndex=own_col[0],
            baseVisualShapeIndex=hidden,
            basePosition=links[0].frame[0],
            baseOrientation=links[0].frame[1],
            baseInertialFramePosition=base_inertial[0],
            baseInertialFrameOrientation=base_inertial[1],
            linkMasses=[r["mass"] for r in spec],
            linkCollisionShapeIndices=[r["col"] for r in spec],
            linkVisualShapeIndices=[hidden] * len(spec),
            linkPositions=[r["tf"][0] for r in spec],
            linkOrientations=[r["tf"][1] for r in spec],
            linkInertialFramePositions=[r["inertial"][0] for r in spec],
            linkInertialFrameOrientations=[r["inertial"][1] for r in spec],
            linkParentIndices=[r["parent"] for r in spec],
            linkJointTypes=[r["type"] for r in spec],
            linkJointAxis=[(0.0, 0.0, 1.0)] * len(spec),
            flags=p.URDF_USE_SELF_COLLISION,
            physicsClientId=c,
        )
    p.changeDynamics(uid, -1, linearDamping=0.0, angularDamping=0.0, physicsClientId=c)
    if not body.fixed:
        p.changeDynamics(uid, -1, localInertiaDiagonal=base_inertia, physicsClientId=c)
    for i, link in enumerate(links[1:], start=1):
        row = rows[i]
        p.changeDynamics(uid, row, localInertiaDiagonal=spec[row]["inertia"], physicsClientId=c)
        j = link.joint.joint if link.joint is not None else None
        if j is not None and j.kind in ("revolute", "prismatic"):
            p.resetJointState(uid, row, j.position, physicsClientId=c)
        elif j is not None and j.kind == "spherical" and getattr(j, "spherical_rotation", None):
            p.resetJointStateMultiDof(uid, row, list(j.spherical_rotation), physicsClientId=c)
    _materials(c, uid, body, parts)
    made = Created(uid, rows, parts)
    made.looks = [
        (uid, rows[i], not (body.fixed and i == 0), link.frame, part)
        for i, link in enumerate(body.links)
        for part, _owner in link.parts
        if part.visible and part.mesh.visible
    ]
    return made


def _preorder(spec: list[dict]) -> list[int]:
    """Link order as pybullet numbers links: depth first from the base, children in the order
    given. Listing the links in that order makes a link's index its position in the list."""
    children: dict[int, list[int]] = {}
    for k, row in enumerate(spec):
        children.setdefault(row["parent"] - 1, []).append(k)
    order: list[int] = []
    stack = list(reversed(children.get(-1, [])))
    while stack:
        k = stack.pop()
        order.append(k)
        stack.extend(reversed(children.get(k, [])))
    return order


def _materials(c: int, uid: int, body: Body, parts: list) -> None:
    done: set[int] = set()
    for row, planned, _part, owner in parts:
        if row in done:
            continue
        done.add(row)
        d = owner.shape.dynamics if owner.shape is not None else None
        carrier = body.links[planned].carrier
        if planned > 0 or not body.fixed:  # a moving link: its dynamic shape's material
            if carrier is not None and carrier.shape is not None:
                d = carrier.shape.dynamics
        friction = DEFAULT_FRICTION if d is None or d.friction is None else d.friction
        p.changeDynamics(
            uid,
            row,
            lateralFriction=friction,
            rollingFriction=0.0,
            spinningFriction=0.0,
            restitution=0.0,
            physicsClientId=c,
        )
        respondable = any(pt.respondable for r, _, pt, _ in parts if r == row)
        group, mask = collision_group(respondable, body.fixed and planned == 0)
        if not any(o.detectable for r, _, _, o in parts if r == row):
            mask &= ~S.RAY  # proximity sensors' rays pass through it, as in CoppeliaSim
        p.setCollisionFilterGroupMask(uid, row, group, mask, physicsClientId=c)


def create_visuals(client: int, looks: list) -> list[Visual]:
    """The visual-only bodies of a scene (made when it is first drawn, so that runs that draw
    nothing do not pay for them); those on moving links are returned for ``sync_visuals``."""
    out: list[Visual] = []
    loaded: dict[str, int] = {}  # texture file -> pybullet texture id, once per client
    for uid, row, moving, frame, part in looks:
        vis = S.create_visual(client, part)
        if vis < 0:
            continue
        v_uid = p.createMultiBody(
            0, -1, vis, basePosition=frame[0], baseOrientation=frame[1], physicsClientId=client
        )
        # set again on the body: pybullet's EGL renderer takes colours from here only
        p.changeVisualShape(v_uid, -1, rgbaColor=S.look_color(part.mesh), physicsClientId=client)
        texture = part.mesh.texture
        if texture is not None and texture.image is not None and S.textured_mesh(part):
            path = texture_file(texture.image, not texture.repeat_u, not texture.repeat_v)
            if path not in loaded:
                loaded[path] = p.loadTexture(path, physicsClientId=client)
            p.changeVisualShape(v_uid, -1, textureUniqueId=loaded[path], physicsClientId=client)
        if moving:
            out.append(Visual(v_uid, uid, row, IDENTITY_TF))
    return out


def collision_group(respondable: bool, fixed: bool) -> tuple[int, int]:
    if not respondable:
        return S.DETECTABLE, S.RAY
    if fixed:
        return STATIC, S.RESPONDABLE | S.RAY
    return S.RESPONDABLE, S.RESPONDABLE | STATIC | S.RAY
