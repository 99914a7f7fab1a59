"""The scenes CoppeliaSim's own ZeroMQ examples load, written by this project to match them.

CoppeliaRobotics/zmqRemoteApi's Python examples (``pController.py``,
``synchronousImageTransmission.py``, ``simpleMovement.py``) load scenes from CoppeliaSim's scene
collection (``sim.getStringParam(sim.stringparam_scenedefaultdir) + '/messaging/...ttt'``),
which is not ours to ship. These are scenes of our own with the objects those examples name
and what their comments describe; nothing of CoppeliaSim's scenes is copied:

- ``pControllerViaRemoteApi``: ``/Cuboid[0]/joint``, a motor (velocity control, max force
  settable) turning an arm in a vertical plane on a fixed post;
- ``synchronousImageTransmissionViaRemoteApi``: ``/VisionSensor`` looking down at a turntable
  of coloured blocks, and ``/PassiveVisionSensor``, whose image the script sets;
- ``movementViaRemoteApi``: ``/blueRobot`` and ``/redRobot``, two 7-joint arms (kinematic
  joints, all aliased ``joint``), and ``/greenRobot`` with a ``target`` dummy.

``python -m sims.remote_api.example_scenes`` writes them as ``.simscene.xml`` to
``sims/scene/bundled/messaging/`` (tests check the files equal what this writes): with
``stringparam_scenedefaultdir`` naming ``sims/scene/bundled`` (CoppeliaSim's scenes folder)
and ``sim.loadScene`` reading ``X.simscene.xml`` for a missing ``X.ttt``, the examples' paths
find them.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

from sims.scene.model import (
    Dynamics,
    JointData,
    Mesh,
    Pose,
    Scene,
    SceneObject,
    ShapeData,
    VisionSensorData,
)

#: CoppeliaSim keeps these in its scenes folder, under messaging/; ours is sims/scene/bundled/
OUT = Path(__file__).resolve().parents[1] / "scene" / "bundled" / "messaging"
GREY, STEEL = (0.55, 0.57, 0.6), (0.75, 0.76, 0.78)


def _q_axis(axis: tuple[float, float, float], angle: float) -> tuple[float, float, float, float]:
    s = math.sin(angle / 2)
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2))


class _Builder:
    def __init__(self) -> None:
        self.objects: list[SceneObject] = []

    def add(self, name: str, kind: str, parent: int | None, pose: Pose, **fields) -> int:
        handle = len(self.objects)
        alias = fields.pop("alias", name.rstrip("0123456789") or name)
        self.objects.append(
            SceneObject(handle, name, kind, parent=parent, pose=pose, alias=alias, **fields)
        )
        return handle

    def box(
        self,
        name: str,
        parent: int | None,
        pose: Pose,
        size: tuple[float, float, float],
        *,
        mass: float = 1.0,
        static: bool = True,
        color=GREY,
        alias: str | None = None,
        model_base: bool = False,
    ) -> int:
        x, y, z = size
        inertia = (
            mass * (y * y + z * z) / 12,
            mass * (x * x + z * z) / 12,
            mass * (x * x + y * y) / 12,
        )
        shape = ShapeData(
            meshes=(Mesh(primitive="cuboid", size=size, color=color),),
            dynamics=Dynamics(static=static, respondable=True, mass=mass, inertia=inertia),
        )
        return self.add(
            name, "shape", parent, pose, shape=shape, model_base=model_base,
            **({"alias": alias} if alias else {}),
        )  # fmt: skip

    def scene(self, name: str) -> Scene:
        return Scene(objects=tuple(self.objects), source=f"{name}.simscene.xml", format="xml")


def p_controller() -> Scene:
    b = _Builder()
    post = b.box("Cuboid", None, Pose((0.0, 0.0, 0.3)), (0.1, 0.1, 0.6), model_base=True)
    axis_horizontal = _q_axis((1.0, 0.0, 0.0), -math.pi / 2)  # joint z along +y
    joint = b.add(
        "joint",
        "joint",
        post,
        Pose((0.0, 0.06, 0.25), axis_horizontal),
        joint=JointData(
            kind="revolute", mode="velocity", cyclic=True, motor_enabled=True,
            control_enabled=False, target_velocity=0.0, max_force=100.0,
        ),
    )  # fmt: skip
    b.box(
        "Cuboid0", joint, Pose((0.2, 0.0, 0.04)), (0.4, 0.04, 0.04), mass=1.0, static=False,
        color=(0.85, 0.45, 0.2), alias="Cuboid",
    )  # fmt: skip
    return b.scene("pControllerViaRemoteApi")


def image_transmission() -> Scene:
    b = _Builder()
    table = b.box("Base", None, Pose((0.0, 0.0, 0.05)), (0.3, 0.3, 0.1), model_base=True)
    spin = b.add(
        "TurntableJoint", "joint", table, Pose((0.0, 0.0, 0.05)),
        joint=JointData(kind="revolute", mode="velocity", cyclic=True, motor_enabled=True,
                        target_velocity=0.8, max_force=50.0),
    )  # fmt: skip
    plate = b.box(
        "Turntable", spin, Pose((0.0, 0.0, 0.01)), (0.5, 0.5, 0.02), mass=1.0, static=False,
        color=(0.9, 0.9, 0.9),
    )  # fmt: skip
    colors = [(0.9, 0.15, 0.15), (0.15, 0.7, 0.2), (0.2, 0.3, 0.9), (0.95, 0.8, 0.1)]
    for k, color in enumerate(colors):
        angle = k * math.pi / 2
        b.box(
            f"Block{k}", plate, Pose((0.15 * math.cos(angle), 0.15 * math.sin(angle), 0.05)),
            (0.08, 0.08, 0.08), mass=0.2, static=False, color=color, alias="Block",
        )  # fmt: skip
    down = _q_axis((1.0, 0.0, 0.0), math.pi)  # looking along -z (the sensor's +z points down)
    sensor = VisionSensorData(resolution=(128, 128), view_angle=math.radians(60), far=3.0)
    b.add("VisionSensor", "vision_sensor", None, Pose((0.0, 0.0, 0.9), down),
          vision_sensor=sensor)  # fmt: skip
    b.add("PassiveVisionSensor", "vision_sensor", None, Pose((0.8, 0.0, 0.9), down),
          vision_sensor=sensor)  # fmt: skip
    return b.scene("synchronousImageTransmissionViaRemoteApi")


def _arm(b: _Builder, name: str, x: float, color) -> None:
    """A 7-joint arm: base, then joints about z, y, z, y, z, y, z, each with a link."""
    base = b.box(name, None, Pose((x, 0.0, 0.05)), (0.16, 0.16, 0.1), color=GREY,
                 model_base=True)  # fmt: skip
    parent, height = base, 0.05
    turn_y = _q_axis((1.0, 0.0, 0.0), -math.pi / 2)  # joint z along +y
    for k in range(7):
        about_y = k % 2 == 1
        joint = b.add(
            f"{name}_joint{k}",
            "joint", parent, Pose((0.0, 0.0, height), turn_y if about_y else (0, 0, 0, 1)),
            alias="joint",
            joint=JointData(kind="revolute", mode="passive", cyclic=True),
        )  # fmt: skip
        length = 0.16
        link_pose = Pose((0.0, -length / 2, 0.0)) if about_y else Pose((0.0, 0.0, length / 2))
        size = (0.06, length, 0.06) if about_y else (0.06, 0.06, length)
        link = b.box(
            f"{name}_link{k}", joint, link_pose, size, color=color if k % 2 else STEEL,
            alias="link",
        )  # fmt: skip
        parent = link
        height = length / 2  # from the link's centre to its end, along the chain
        if about_y:  # the next joint sits at the link's far end, its axis up the chain again
            parent = b.add(
                f"{name}_frame{k}", "dummy", link, Pose((0.0, -length / 2, 0.0),
                _q_axis((1.0, 0.0, 0.0), math.pi / 2)), alias="frame",
            )  # fmt: skip
            height = 0.0


def movement() -> Scene:
    b = _Builder()
    _arm(b, "blueRobot", -0.6, (0.2, 0.35, 0.9))
    _arm(b, "redRobot", 0.0, (0.9, 0.2, 0.2))
    green = b.box("greenRobot", None, Pose((0.6, 0.0, 0.05)), (0.16, 0.16, 0.1),
                  color=(0.2, 0.75, 0.3), model_base=True)  # fmt: skip
    b.add("target", "dummy", green, Pose((0.0, 0.1, 0.45)), alias="target")
    return b.scene("movementViaRemoteApi")


SCENES = {
    "pControllerViaRemoteApi": p_controller,
    "synchronousImageTransmissionViaRemoteApi": image_transmission,
    "movementViaRemoteApi": movement,
}


def texts() -> dict[str, str]:
    from sims.scene.xml_write import write_xml

    return {f"{name}.simscene.xml": write_xml(build()) for name, build in SCENES.items()}


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    for name, text in texts().items():
        (OUT / name).write_text(text, encoding="utf-8")
        print(OUT / name)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
