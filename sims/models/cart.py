"""An EV3-style differential-drive cart in a walled arena with obstacles (the course's cart).

The course scene only fixes the wheel motor names ``left_m``/``right_m`` (velocity control, the
keyboard script's 2 rad/s maximum); the rest is an EV3-like build: 56 mm wheels on a 130 mm
track, a brick-sized chassis, a low-friction caster ball at the back and a front proximity
sensor (a 7-ray fan, 50 degrees wide, 0.5 m range). Forward is the body's +x; a positive wheel
velocity drives forward.

Scene options: ``arena`` (bool, walls around a 3 m square), ``obstacles`` (how many boxes and
cylinders; placed from the World seed so a seed fixes the layout), ``start`` ((x, y, yaw_deg)).
"""

from __future__ import annotations

import math
import random

from sims.models.common import (
    CameraSetup,
    JointRef,
    ObjectRef,
    RaySensor,
    SceneModel,
    add_checker_floor,
    quat_from_euler,
    quat_rotating,
)
from sims.quiet import pybullet as p

WHEEL_RADIUS, WHEEL_WIDTH, WHEEL_MASS = 0.028, 0.022, 0.05
TRACK = 0.13  # distance between wheel centres
CHASSIS_HALF = (0.075, 0.05, 0.03)
CHASSIS_CENTRE = (-0.03, 0.0, 0.062)  # relative to the axle midpoint on the floor
CHASSIS_MASS = 0.6
CASTER_RADIUS, CASTER_AT, CASTER_MASS = 0.014, (-0.09, 0.0, 0.014), 0.02
MOTOR_MAX_TORQUE = 0.4  # N*m, about an EV3 large motor's stall torque
SENSOR_ORIGIN = (CHASSIS_CENTRE[0] + CHASSIS_HALF[0] + 0.002, 0.0, 0.045)
SENSOR_RANGE = 0.5
ARENA_HALF = 1.5
WALL_HEIGHT, WALL_THICKNESS = 0.12, 0.04


def build(
    client: int,
    seed: int = 0,
    arena: bool = True,
    obstacles: int = 6,
    start: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> SceneModel:
    add_checker_floor(client, 2 * ARENA_HALF + 1.0, 0.25)
    blockers = _walls(client) if arena else []
    blockers += _obstacles(client, seed, obstacles, start)
    x0, y0, yaw0 = start
    cart = _cart(client, (x0, y0), math.radians(yaw0))
    joints = [
        JointRef(name, cart, index, max_force=MOTOR_MAX_TORQUE, mode="velocity")
        for index, name in ((0, "left_m"), (1, "right_m"))
    ]
    objects = [
        ObjectRef("cart", cart, -1),
        ObjectRef("left_wheel", cart, 0),
        ObjectRef("right_wheel", cart, 1),
        ObjectRef("caster", cart, 2),
    ]
    sensors = [
        RaySensor(
            "Proximity_sensor", cart, -1, SENSOR_ORIGIN, SENSOR_RANGE, spread_deg=50.0, count=7
        )
    ]
    return SceneModel(
        robot="cart",
        forward_axis=(1.0, 0.0, 0.0),
        objects=objects,
        joints=joints,
        sensors=sensors,
        obstacles=blockers,
        camera=CameraSetup(distance=0.9, yaw=-60.0, pitch=-35.0, target_z=0.05),
    )


def _cart(client: int, at: tuple[float, float], yaw: float) -> int:
    c = client
    chassis_col = p.createCollisionShape(
        p.GEOM_BOX,
        halfExtents=CHASSIS_HALF,
        collisionFramePosition=CHASSIS_CENTRE,
        physicsClientId=c,
    )
    chassis_vis = p.createVisualShapeArray(
        [p.GEOM_BOX, p.GEOM_BOX],
        halfExtents=[CHASSIS_HALF, (0.012, 0.03, 0.012)],
        visualFramePositions=[CHASSIS_CENTRE, SENSOR_ORIGIN],
        physicsClientId=c,
    )
    wheel_orn = quat_rotating((0, 0, 1), (0, 1, 0))
    wheel_col = p.createCollisionShape(
        p.GEOM_CYLINDER,
        radius=WHEEL_RADIUS,
        height=WHEEL_WIDTH,
        collisionFrameOrientation=wheel_orn,
        physicsClientId=c,
    )
    wheel_vis = p.createVisualShape(
        p.GEOM_CYLINDER,
        radius=WHEEL_RADIUS,
        length=WHEEL_WIDTH,
        visualFrameOrientation=wheel_orn,
        rgbaColor=(0.1, 0.1, 0.1, 1),
        physicsClientId=c,
    )
    caster_col = p.createCollisionShape(p.GEOM_SPHERE, radius=CASTER_RADIUS, physicsClientId=c)
    caster_vis = p.createVisualShape(
        p.GEOM_SPHERE, radius=CASTER_RADIUS, rgbaColor=(0.7, 0.7, 0.7, 1), physicsClientId=c
    )
    axle = (0.0, 0.0, WHEEL_RADIUS)
    cart = p.createMultiBody(
        baseMass=CHASSIS_MASS,
        baseCollisionShapeIndex=chassis_col,
        baseVisualShapeIndex=chassis_vis,
        basePosition=(at[0], at[1], 0.0),
        baseOrientation=quat_from_euler(0, 0, yaw),
        baseInertialFramePosition=CHASSIS_CENTRE,
        linkMasses=[WHEEL_MASS, WHEEL_MASS, CASTER_MASS],
        linkCollisionShapeIndices=[wheel_col, wheel_col, caster_col],
        linkVisualShapeIndices=[wheel_vis, wheel_vis, caster_vis],
        linkPositions=[(axle[0], TRACK / 2, axle[2]), (axle[0], -TRACK / 2, axle[2]), CASTER_AT],
        linkOrientations=[(0, 0, 0, 1)] * 3,
        linkInertialFramePositions=[(0, 0, 0)] * 3,
        linkInertialFrameOrientations=[(0, 0, 0, 1)] * 3,
        linkParentIndices=[0, 0, 0],
        linkJointTypes=[p.JOINT_REVOLUTE, p.JOINT_REVOLUTE, p.JOINT_FIXED],
        linkJointAxis=[(0, 1, 0), (0, 1, 0), (0, 0, 1)],
        physicsClientId=c,
    )
    p.changeVisualShape(cart, -1, rgbaColor=(0.85, 0.85, 0.80, 1), physicsClientId=c)
    for wheel in (0, 1):
        p.changeDynamics(
            cart,
            wheel,
            lateralFriction=1.0,
            rollingFriction=0.0,
            spinningFriction=0.0,
            physicsClientId=c,
        )
    p.changeDynamics(
        cart, 2, lateralFriction=0.02, rollingFriction=0.0, spinningFriction=0.0, physicsClientId=c
    )
    return cart


def _box(
    client: int,
    centre: tuple[float, float, float],
    half: tuple[float, float, float],
    rgba: tuple[float, ...],
    yaw: float = 0.0,
) -> int:
    col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=client)
    vis = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=rgba, physicsClientId=client)
    return p.createMultiBody(
        0,
        col,
        vis,
        basePosition=centre,
        baseOrientation=quat_from_euler(0, 0, yaw),
        physicsClientId=client,
    )


def _walls(client: int) -> list[int]:
    h, t, z = ARENA_HALF, WALL_THICKNESS / 2, WALL_HEIGHT / 2
    grey = (0.55, 0.45, 0.40, 1)
    return [
        _box(client, (0, h + t, z), (h + 2 * t, t, z), grey),
        _box(client, (0, -h - t, z), (h + 2 * t, t, z), grey),
        _box(client, (h + t, 0, z), (t, h, z), grey),
        _box(client, (-h - t, 0, z), (t, h, z), grey),
    ]


def _obstacles(client: int, seed: int, count: int, start: tuple[float, float, float]) -> list[int]:
    """Boxes and cylinders at seeded places, clear of the start and 0.35 m apart (passable)."""
    rng = random.Random(f"cart-obstacles-{seed}")
    placed: list[tuple[float, float, float]] = []  # x, y, radius
    bodies = []
    tries = 0
    while len(placed) < count and tries < 1000:
        tries += 1
        radius = rng.uniform(0.06, 0.14)
        x = rng.uniform(-ARENA_HALF + 0.3, ARENA_HALF - 0.3)
        y = rng.uniform(-ARENA_HALF + 0.3, ARENA_HALF - 0.3)
        if math.hypot(x - start[0], y - start[1]) < 0.45 + radius:
            continue
        if any(math.hypot(x - ox, y - oy) < r + radius + 0.35 for ox, oy, r in placed):
            continue
        placed.append((x, y, radius))
        colour = (0.20 + 0.1 * (len(placed) % 3), 0.55, 0.30, 1)
        if len(placed) % 2:
            bodies.append(
                _box(
                    client,
                    (x, y, 0.08),
                    (radius * 0.8, radius * 0.8, 0.08),
                    colour,
                    yaw=rng.uniform(0, math.pi / 2),
                )
            )
        else:
            col = p.createCollisionShape(
                p.GEOM_CYLINDER, radius=radius, height=0.16, physicsClientId=client
            )
            vis = p.createVisualShape(
                p.GEOM_CYLINDER,
                radius=radius,
                length=0.16,
                rgbaColor=colour,
                physicsClientId=client,
            )
            bodies.append(
                p.createMultiBody(0, col, vis, basePosition=(x, y, 0.08), physicsClientId=client)
            )
    return bodies
