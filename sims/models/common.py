"""What a scene builder hands to :class:`sims.world.World`, plus small geometry helpers.

A model builder creates bodies in one pybullet client and returns a :class:`SceneModel`: the
CoppeliaSim-style names of its objects and joints and how each maps onto pybullet ids. The World
only ever goes through this table, so the name/handle contract does not depend on pybullet ids.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from sims.quiet import pybullet as p

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]
IDENTITY: Quat = (0.0, 0.0, 0.0, 1.0)
Tf = tuple[Vec3, Quat]
TILE_DEPTH = 0.003  # visual depth of the floor's checker tiles (m)
MAX_COMPOUND = 16  # pybullet keeps at most 16 shapes of a createVisualShapeArray


@dataclass(frozen=True)
class ObjectRef:
    """A named object: a pybullet link (-1 = base) plus a fixed offset to the CoppeliaSim frame."""

    name: str
    body: int
    link: int
    offset_pos: Vec3 = (0.0, 0.0, 0.0)
    offset_orn: Quat = IDENTITY
    via: str = ""  # hangs from this loop-closing joint: pose = its moved frame x ``via_offset``
    via_offset: tuple[Vec3, Quat] = ((0.0, 0.0, 0.0), IDENTITY)


@dataclass(frozen=True)
class Closure:
    """A joint that closes a kinematic loop and has no pybullet joint of its own (constraints
    hold it: sims/scene/loops.py). Its parent link is the JointRef's ``body``/``index``; its
    position is the turn (about z) of ``child_frame`` on the child link relative to
    ``parent_frame`` on the parent link (frames relative to the links' frames)."""

    child_body: int
    child_link: int
    parent_frame: Tf
    child_frame: Tf


@dataclass(frozen=True)
class JointRef:
    """A named joint. CoppeliaSim angle = ``zero + pybullet angle`` (radians).

    Building each robot in its saved pose makes pybullet's zero that pose, so ``zero`` is the
    saved CoppeliaSim angle. ``lower``/``upper`` are CoppeliaSim limits (None = cyclic).
    """

    name: str
    body: int
    index: int
    zero: float = 0.0
    max_force: float = 1.0
    position_gain: float = 0.1
    velocity_gain: float = 1.0
    max_velocity: float | None = None
    lower: float | None = None
    upper: float | None = None
    mode: str = "position"  # initial motor mode: "position", "velocity", "free", "spring", "hold"
    friction_torque: float = 0.0  # used by mode "free": a velocity motor at 0 with this torque
    kind: str = "revolute"  # "revolute", "prismatic" or "spherical"
    own_frame: bool = False  # object pose = the joint's own frame (without its displacement)
    spring_k: float = 0.0  # mode "spring": torque = -k (q - target) - c dq/dt, capped
    spring_c: float = 0.0
    initial_velocity: float = 0.0  # mode "velocity": the saved target velocity
    initial_target: float | None = None  # mode "position"/"spring": saved target (None: zero)
    coppelia_mode: int | None = None  # the mode CoppeliaSim reports (0 passive, 1 motion...)
    closure: Closure | None = None  # a loop's closing joint: no pybullet joint of its own


@dataclass(frozen=True)
class RaySensor:
    """A proximity sensor: a fan of ``count`` rays from ``origin`` (link frame) around the link's
    +x axis, ``spread_deg`` wide in its x-y plane, like CoppeliaSim's cone-shaped sensors."""

    name: str
    body: int
    link: int
    origin: Vec3
    max_range: float
    spread_deg: float = 0.0
    count: int = 1

    def rays(self) -> list[Vec3]:
        """Unit directions in the link frame, left (+y side) to right."""
        if self.count == 1:
            return [(1.0, 0.0, 0.0)]
        half = math.radians(self.spread_deg) / 2
        angles = [half - 2 * half * i / (self.count - 1) for i in range(self.count)]
        return [(math.cos(a), math.sin(a), 0.0) for a in angles]


@dataclass(frozen=True)
class ProxSensor:
    """A proximity sensor of a scene file: its frame on a link (z = sensing direction, as in
    CoppeliaSim) and the rays that sample its detection volume, (start, end) in that frame."""

    name: str
    body: int
    link: int
    offset_pos: Vec3
    offset_orn: Quat
    rays: tuple[tuple[Vec3, Vec3], ...]
    explicit: bool = False  # explicit handling: CoppeliaSim's main script leaves it alone


@dataclass(frozen=True)
class TreeNode:
    """One object of a scene file's tree, in handle order: ``kind`` as in sims.scene.model,
    ``parent`` the parent's name (None at the top)."""

    name: str
    kind: str
    parent: str | None = None
    alias: str = ""


@dataclass(frozen=True)
class CameraSetup:
    """Default chase camera for a scene: distance (m), yaw/pitch (deg), height of the target."""

    distance: float
    yaw: float
    pitch: float
    target_z: float


@dataclass
class SceneModel:
    """Everything the World needs to know about one built scene."""

    robot: str  # the main object (camera follows it, scenarios track it)
    forward_axis: Vec3  # the robot object's local axis that points "forward"
    objects: list[ObjectRef]
    joints: list[JointRef]
    sensors: list[RaySensor] = field(default_factory=list)
    obstacles: list[int] = field(default_factory=list)  # body ids a robot must not touch
    camera: CameraSetup = CameraSetup(0.6, 30.0, -30.0, 0.05)
    # Scene files (sims.scene.build): every object in handle order, sensors with their volume,
    # the scene's own objects by name (vision sensor data...), and what the builder approximated.
    tree: list[TreeNode] = field(default_factory=list)
    prox: list[ProxSensor] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


def quat_from_euler(roll: float, pitch: float, yaw: float) -> Quat:
    return tuple(p.getQuaternionFromEuler((roll, pitch, yaw)))  # type: ignore[return-value]


def quat_rotating(a: Vec3, b: Vec3) -> Quat:
    """Shortest rotation that turns unit-ish vector ``a`` into ``b`` (used to aim cylinders)."""
    ax, ay, az = _unit(a)
    bx, by, bz = _unit(b)
    cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    dot = ax * bx + ay * by + az * bz
    if dot < -0.999999:  # opposite: rotate 180 degrees about any perpendicular axis
        perp = (1.0, 0.0, 0.0) if abs(ax) < 0.9 else (0.0, 1.0, 0.0)
        px, py, pz = _unit(
            (ay * perp[2] - az * perp[1], az * perp[0] - ax * perp[2], ax * perp[1] - ay * perp[0])
        )
        return (px, py, pz, 0.0)
    w = 1.0 + dot
    n = math.sqrt(cx * cx + cy * cy + cz * cz + w * w)
    return (cx / n, cy / n, cz / n, w / n)


def _unit(v: Vec3) -> Vec3:
    n = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
    return (v[0] / n, v[1] / n, v[2] / n)


def sub(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def midpoint(a: Vec3, b: Vec3) -> Vec3:
    return ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2)


def distance(a: Vec3, b: Vec3) -> float:
    return math.dist(a, b)


def add_checker_floor(
    client: int,
    size: float,
    tile: float,
    pattern: float | None = None,
    thickness: float = 0.02,
    colors: tuple[tuple[float, ...], tuple[float, ...]] = (
        (0.82, 0.84, 0.86, 1.0),
        (0.62, 0.66, 0.72, 1.0),
    ),
) -> int:
    """A static floor box, top surface at z=0, with a checker pattern of thin dark tiles.

    The pattern is geometry rather than a texture file so the scene needs no data files, and it
    makes motion visible when the camera follows the robot. Tiles are boxes, not a vertex
    mesh, because pybullet's EGL renderer cannot draw meshes given as vertex arrays. Only the
    central ``pattern`` metres are tiled (default: all of it) to bound the shape count.
    """
    half = size / 2
    col = p.createCollisionShape(
        p.GEOM_BOX, halfExtents=(half, half, thickness / 2), physicsClientId=client
    )
    # The light surface is drawn 3 mm low and the tiles fill up to z=0: thinner tiles are lost
    # to depth-buffer precision, and nothing drawn sticks out above the real floor.
    base_vis = p.createVisualShape(
        p.GEOM_BOX,
        halfExtents=(half, half, thickness / 2),
        visualFramePosition=(0, 0, -TILE_DEPTH),
        rgbaColor=colors[0],
        physicsClientId=client,
    )
    floor = p.createMultiBody(
        0, col, base_vis, basePosition=(0, 0, -thickness / 2), physicsClientId=client
    )
    p.changeDynamics(floor, -1, lateralFriction=1.0, physicsClientId=client)
    p.changeVisualShape(floor, -1, specularColor=(0, 0, 0), physicsClientId=client)
    span = min(size, pattern or size)
    n = max(1, round(span / tile))
    corner = -n * tile / 2
    positions = [
        (corner + (i + 0.5) * tile, corner + (j + 0.5) * tile, -TILE_DEPTH / 2)
        for i in range(n)
        for j in range(n)
        if (i + j) % 2 == 0
    ]
    for start in range(0, len(positions), MAX_COMPOUND):
        chunk = positions[start : start + MAX_COMPOUND]
        vis = p.createVisualShapeArray(
            [p.GEOM_BOX] * len(chunk),
            halfExtents=[(tile / 2, tile / 2, TILE_DEPTH / 2)] * len(chunk),
            visualFramePositions=chunk,
            physicsClientId=client,
        )
        tiles = p.createMultiBody(0, -1, vis, physicsClientId=client)
        p.changeVisualShape(
            tiles, -1, rgbaColor=colors[1], specularColor=(0, 0, 0), physicsClientId=client
        )
    return floor
