"""The course's 2W1A robot ("two wheels, one arm"), built in code from the reference geometry.

Source: ``shared/reference/2w1a-robot.md`` (decoded from the course scene ``2w1a.ttt``). All
positions below are world coordinates of the saved pose in metres; each link is built in that
pose, so pybullet's joint zero is the saved CoppeliaSim angle (150/120/250 degrees) and
``JointRef(zero=..., sign=+1)`` maps between the two conventions.

Modelling choices the reference does not pin down (kept deliberately simple):
- The body's mass centre is the volume-weighted centre of cube + tail, not the frame origin.
- The tail is five capsules tapering from 45 mm to 5 mm; it rests ~5 cm above the floor in the
  saved pose and drags once the hand lifts off (the body tips back onto it).
- Arm joints: pybullet POSITION_CONTROL with positionGain 0.1. pybullet's motor aims for a joint
  velocity of ``gain * error / timestep``, the same form as CoppeliaSim's built-in controller
  with P = 0.1, so the gain carries over directly. Speed is capped at 360 deg/s.
- No self-collision (see SELF_COLLISION_FLAGS), so commanded targets are always reached.
- Measured over 90 random moves (6 seeds): the body moves a median 4 cm per move (90th
  percentile 20 cm), and on a 7 cm track it tips onto its side or back in about a third of the
  moves when the arm swings out sideways; the tail and the arm then prop it.
"""

from __future__ import annotations

import math

from sims.models.common import (
    CameraSetup,
    JointRef,
    ObjectRef,
    SceneModel,
    Vec3,
    add_checker_floor,
    distance,
    midpoint,
    quat_from_euler,
    quat_rotating,
    sub,
)
from sims.quiet import pybullet as p

# Saved-pose geometry (world frame), from the reference table.
BODY_FRAME: Vec3 = (-0.0201, 0.0, 0.070)
CUBE_CENTRE: Vec3 = (0.0435, 0.0, 0.070)
CUBE_SIDE = 0.045
TAIL_START: Vec3 = (0.021, 0.0, 0.070)  # back face of the cube
TAIL_END: Vec3 = (-0.100, 0.0, 0.050)
TAIL_DIAMETERS = (0.045, 0.005)
TAIL_SEGMENTS = 5
BODY_MASS = 0.560
WHEEL_RADIUS, WHEEL_WIDTH, WHEEL_MASS = 0.040, 0.010, 0.402
WHEEL_CENTRES = {"Left": (0.050, 0.035, 0.040), "Right": (0.050, -0.035, 0.040)}
WHEEL_FRICTION_TORQUE = 0.01
SHOULDER: Vec3 = (0.0675, 0.0, 0.090)
ELBOW: Vec3 = (0.1303, 0.0, 0.0798)
WRIST: Vec3 = (0.1930, 0.0, 0.1160)
FOOT: Vec3 = (0.1845, 0.0, 0.0046)
FOOT_RADIUS = 0.005
HAND_FRAME_DISTANCE = 0.052
ARM_MASS, FOREARM_MASS, HAND_MASS = 0.05, 0.15, 0.10
SAVED_DEG = {"ShoulderMotor": 150.0, "ElbowMotor": 120.0, "WristMotor": 250.0}
ARM_MAX_TORQUE = 2.5
ARM_POSITION_GAIN = 0.1
ARM_MAX_VELOCITY = math.radians(360.0)
LIMITS_DEG = (0.0, 300.0)
# No self-collision: the arm may pass through the body. With it on (excluding parent links),
# 10% of random targets end 40+ degrees short, blocked by the body; flips were as frequent.
SELF_COLLISION_FLAGS = 0

# CoppeliaSim's body frame has its z axis along world +x: a +90 degree turn about y.
BODY_FRAME_ORN = quat_from_euler(0.0, math.pi / 2, 0.0)


def _tail_segments() -> list[tuple[Vec3, float, float]]:
    """(centre, radius, length) of each tail capsule, front to back."""
    segs = []
    length = distance(TAIL_START, TAIL_END) / TAIL_SEGMENTS
    d0, d1 = TAIL_DIAMETERS
    for i in range(TAIL_SEGMENTS):
        t = (i + 0.5) / TAIL_SEGMENTS
        centre = tuple(TAIL_START[k] + (TAIL_END[k] - TAIL_START[k]) * t for k in range(3))
        radius = (d0 + (d1 - d0) * t) / 2
        segs.append((centre, radius, length))  # type: ignore[arg-type]
    return segs


def _body_com() -> Vec3:
    """Volume-weighted centre of the cube and the tail capsules (uniform density)."""
    parts = [(CUBE_CENTRE, CUBE_SIDE**3)]
    parts += [(c, math.pi * r * r * length) for c, r, length in _tail_segments()]
    total = sum(v for _, v in parts)
    return tuple(sum(c[k] * v for c, v in parts) / total for k in range(3))  # type: ignore[return-value]


def _shapes(client: int, frame: Vec3, items: list[dict]) -> tuple[int, int]:
    """Collision + visual compound for one link; item positions are world (saved pose)."""
    kinds, radii, extents, lengths, positions, orns, colors = [], [], [], [], [], [], []
    for it in items:
        kinds.append(it["type"])
        radii.append(it.get("radius", 0.0))
        extents.append(it.get("half", (0.0, 0.0, 0.0)))
        lengths.append(it.get("length", 0.0))
        positions.append(sub(it["at"], frame))
        orns.append(it.get("orn", (0.0, 0.0, 0.0, 1.0)))
        colors.append(it.get("color", (0.8, 0.8, 0.8, 1.0)))
    col = p.createCollisionShapeArray(
        kinds,
        radii=radii,
        halfExtents=extents,
        lengths=lengths,
        collisionFramePositions=positions,
        collisionFrameOrientations=orns,
        physicsClientId=client,
    )
    vis = p.createVisualShapeArray(
        kinds,
        radii=radii,
        halfExtents=extents,
        lengths=lengths,
        visualFramePositions=positions,
        visualFrameOrientations=orns,
        physicsClientId=client,
    )
    return col, vis


def _along(a: Vec3, b: Vec3, t: float) -> Vec3:
    return tuple(a[k] + (b[k] - a[k]) * t for k in range(3))  # type: ignore[return-value]


def build(client: int, seed: int = 0, floor_size: float = 5.0) -> SceneModel:
    """Create the floor and the robot in ``client``; return its name table."""
    del seed  # the 2W1A scene has no random parts
    add_checker_floor(client, floor_size, 0.1, pattern=3.0)

    body_parts = [{"type": p.GEOM_BOX, "at": CUBE_CENTRE, "half": (CUBE_SIDE / 2,) * 3}]
    axis = sub(TAIL_END, TAIL_START)
    tail_orn = quat_rotating((0.0, 0.0, 1.0), axis)
    for centre, radius, length in _tail_segments():
        body_parts.append(
            {
                "type": p.GEOM_CAPSULE,
                "at": centre,
                "radius": radius,
                "length": length,
                "orn": tail_orn,
            }
        )
    body_col, body_vis = _shapes(client, BODY_FRAME, body_parts)

    wheel_orn = quat_rotating((0.0, 0.0, 1.0), (0.0, 1.0, 0.0))
    forearm_orn = quat_rotating((1.0, 0.0, 0.0), sub(WRIST, ELBOW))
    hand_orn = quat_rotating((0.0, 0.0, 1.0), sub(FOOT, WRIST))
    hand_len = distance(WRIST, FOOT) - FOOT_RADIUS
    plate_y = 0.0193 / 2 + 0.0017  # side plates flank the 19.3 mm wide servo box
    fore_mid = midpoint(ELBOW, WRIST)
    links = [  # name, parent index (0 = base), joint position, joint type, axis, mass, com, parts
        (
            "LeftWheel",
            0,
            WHEEL_CENTRES["Left"],
            p.JOINT_REVOLUTE,
            (0, 1, 0),
            WHEEL_MASS,
            WHEEL_CENTRES["Left"],
            [
                {
                    "type": p.GEOM_CYLINDER,
                    "at": WHEEL_CENTRES["Left"],
                    "radius": WHEEL_RADIUS,
                    "length": WHEEL_WIDTH,
                    "orn": wheel_orn,
                }
            ],
        ),
        (
            "RightWheel",
            0,
            WHEEL_CENTRES["Right"],
            p.JOINT_REVOLUTE,
            (0, 1, 0),
            WHEEL_MASS,
            WHEEL_CENTRES["Right"],
            [
                {
                    "type": p.GEOM_CYLINDER,
                    "at": WHEEL_CENTRES["Right"],
                    "radius": WHEEL_RADIUS,
                    "length": WHEEL_WIDTH,
                    "orn": wheel_orn,
                }
            ],
        ),
        (
            "ArmRespondable",
            0,
            SHOULDER,
            p.JOINT_REVOLUTE,
            (1, 0, 0),
            ARM_MASS,
            midpoint(SHOULDER, ELBOW),
            [
                {
                    "type": p.GEOM_BOX,
                    "at": midpoint(SHOULDER, ELBOW),
                    "half": (0.0203, 0.00965, 0.01665),
                },
                {
                    "type": p.GEOM_BOX,
                    "at": (ELBOW[0] - 0.008, plate_y, ELBOW[2]),
                    "half": (0.0182, 0.0017, 0.00895),
                },
                {
                    "type": p.GEOM_BOX,
                    "at": (ELBOW[0] - 0.008, -plate_y, ELBOW[2]),
                    "half": (0.0182, 0.0017, 0.00895),
                },
            ],
        ),
        (
            "ForearmRespondable",
            3,
            ELBOW,
            p.JOINT_REVOLUTE,
            (0, 1, 0),
            FOREARM_MASS,
            midpoint(ELBOW, WRIST),
            [
                {
                    "type": p.GEOM_BOX,
                    "at": _along(ELBOW, WRIST, 0.3),
                    "half": (0.0203, 0.00965, 0.01665),
                    "orn": forearm_orn,
                },
                {
                    "type": p.GEOM_BOX,
                    "at": (fore_mid[0], plate_y, fore_mid[2]),
                    "half": (0.0335, 0.0017, 0.00895),
                    "orn": forearm_orn,
                },
                {
                    "type": p.GEOM_BOX,
                    "at": (fore_mid[0], -plate_y, fore_mid[2]),
                    "half": (0.0335, 0.0017, 0.00895),
                    "orn": forearm_orn,
                },
            ],
        ),
        (
            "HandRespondable",
            4,
            WRIST,
            p.JOINT_REVOLUTE,
            (0, 1, 0),
            HAND_MASS,
            _along(WRIST, FOOT, 0.55),
            [
                {
                    "type": p.GEOM_BOX,
                    "at": _along(WRIST, FOOT, 0.45),
                    "half": (0.006, 0.00965, hand_len * 0.45),
                    "orn": hand_orn,
                },
                {"type": p.GEOM_SPHERE, "at": FOOT, "radius": FOOT_RADIUS},
            ],
        ),
    ]
    frames = [BODY_FRAME] + [link[2] for link in links]
    kw: dict[str, list] = {
        k: []
        for k in (
            "linkMasses",
            "linkCollisionShapeIndices",
            "linkVisualShapeIndices",
            "linkPositions",
            "linkOrientations",
            "linkInertialFramePositions",
            "linkInertialFrameOrientations",
            "linkParentIndices",
            "linkJointTypes",
            "linkJointAxis",
        )
    }
    for _name, parent, joint_at, jtype, jaxis, mass, com, parts in links:
        col, vis = _shapes(client, joint_at, parts)
        kw["linkMasses"].append(mass)
        kw["linkCollisionShapeIndices"].append(col)
        kw["linkVisualShapeIndices"].append(vis)
        kw["linkPositions"].append(sub(joint_at, frames[parent]))
        kw["linkOrientations"].append((0.0, 0.0, 0.0, 1.0))
        kw["linkInertialFramePositions"].append(sub(com, joint_at))
        kw["linkInertialFrameOrientations"].append((0.0, 0.0, 0.0, 1.0))
        kw["linkParentIndices"].append(parent)
        kw["linkJointTypes"].append(jtype)
        kw["linkJointAxis"].append(jaxis)
    robot = p.createMultiBody(
        baseMass=BODY_MASS,
        baseCollisionShapeIndex=body_col,
        baseVisualShapeIndex=body_vis,
        basePosition=BODY_FRAME,
        baseInertialFramePosition=sub(_body_com(), BODY_FRAME),
        flags=SELF_COLLISION_FLAGS,
        physicsClientId=client,
        **kw,
    )
    _colour(client, robot)
    for link in range(-1, len(links)):
        p.changeDynamics(robot, link, lateralFriction=0.8, physicsClientId=client)
    p.changeDynamics(robot, -1, lateralFriction=0.4, physicsClientId=client)  # the dragging tail
    for wheel in (0, 1):
        p.changeDynamics(
            robot,
            wheel,
            lateralFriction=1.0,
            rollingFriction=0.0,
            spinningFriction=0.0,
            physicsClientId=client,
        )

    lo, hi = (math.radians(v) for v in LIMITS_DEG)
    joints = [
        JointRef(
            "LeftWheelJoint",
            robot,
            0,
            mode="free",
            max_force=1.0,
            friction_torque=WHEEL_FRICTION_TORQUE,
        ),
        JointRef(
            "RightWheelJoint",
            robot,
            1,
            mode="free",
            max_force=1.0,
            friction_torque=WHEEL_FRICTION_TORQUE,
        ),
    ]
    for index, name in ((2, "ShoulderMotor"), (3, "ElbowMotor"), (4, "WristMotor")):
        joints.append(
            JointRef(
                name,
                robot,
                index,
                zero=math.radians(SAVED_DEG[name]),
                max_force=ARM_MAX_TORQUE,
                position_gain=ARM_POSITION_GAIN,
                max_velocity=ARM_MAX_VELOCITY,
                lower=lo,
                upper=hi,
            )
        )
    hand_offset = sub(_along(WRIST, FOOT, HAND_FRAME_DISTANCE / distance(WRIST, FOOT)), WRIST)
    objects = [
        ObjectRef("2W1A", robot, -1, offset_orn=BODY_FRAME_ORN),
        ObjectRef("LeftWheel", robot, 0),
        ObjectRef("RightWheel", robot, 1),
        ObjectRef("ArmRespondable", robot, 2, offset_pos=sub(midpoint(SHOULDER, ELBOW), SHOULDER)),
        ObjectRef("ForearmRespondable", robot, 3, offset_pos=sub(midpoint(ELBOW, WRIST), ELBOW)),
        ObjectRef("HandRespondable", robot, 4, offset_pos=hand_offset),
    ]
    return SceneModel(
        robot="2W1A",
        forward_axis=(0.0, 0.0, 1.0),
        objects=objects,
        joints=joints,
        camera=CameraSetup(distance=0.55, yaw=35.0, pitch=-28.0, target_z=0.06),
    )


def _colour(client: int, robot: int) -> None:
    """Flat colours per link (the compound shapes share one colour per link)."""
    colours = {
        -1: (0.95, 0.55, 0.10, 1),
        0: (0.15, 0.15, 0.15, 1),
        1: (0.15, 0.15, 0.15, 1),
        2: (0.20, 0.45, 0.85, 1),
        3: (0.25, 0.60, 0.95, 1),
        4: (0.85, 0.20, 0.25, 1),
    }
    for link, rgba in colours.items():
        p.changeVisualShape(robot, link, rgbaColor=rgba, physicsClientId=client)
