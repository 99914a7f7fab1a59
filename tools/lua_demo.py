"""The project's own scene whose motion comes from its Lua scripts:
``data/scenes/lua_arm.simscene.xml``.

A post on a floor carries a swinging arm on a position-controlled revolute joint and, on top, a
spinning flag on a velocity-controlled joint. Nothing moves unless the scripts run:

- the arm's non-threaded child script (``sysCall_*`` style) sets the arm joint's target to
  ``0.9 sin(1.2 t)`` each actuation and counts its sensing calls in the integer signal
  ``armPasses`` (a remote API client can read it);
- the flag's threaded child script (V-REP 3.x style, ``sim_call_type`` and ``simWait``) spins
  the flag one way for 2 s, then the other way, forever, yielding at ``simWait``; a remote API
  client can change its speed with the float signal ``flagSpeed``.

``python -m tools.lua_demo OUT`` writes the scene (deterministic: same bytes each time); a test
checks the shipped file against it.
"""

from __future__ import annotations

import math
import sys

from sims.scene.model import (
    Dynamics,
    JointData,
    Mesh,
    Pose,
    Scene,
    SceneObject,
    Script,
    ShapeData,
)

ARM_SCRIPT = """-- swing the arm: a non-threaded child script (CoppeliaSim 4.x callbacks)
function sysCall_init()
    joint = sim.getObjectHandle('ArmJoint')
    passes = 0
end

function sysCall_actuation()
    local t = sim.getSimulationTime()
    sim.setJointTargetPosition(joint, 0.9 * math.sin(1.2 * t))
end

function sysCall_sensing()
    passes = passes + 1
    sim.setIntegerSignal('armPasses', passes)
end
"""

FLAG_SCRIPT = """-- spin the flag: a threaded child script (V-REP 3.x style)
if (sim_call_type == sim_childscriptcall_threaded) then
    local spinner = simGetObjectHandle('FlagJoint')
    local direction = 1
    while simGetSimulationState() ~= sim_simulation_advancing_abouttostop do
        local speed = simGetFloatSignal('flagSpeed') or 3
        simSetJointTargetVelocity(spinner, direction * speed)
        simWait(2)
        direction = -direction
    end
end
"""


ARM_RADIUS = 0.16  # m from the arm joint's axis to the arm's centre


def _box(size: tuple[float, float, float], color: tuple[float, float, float]) -> Mesh:
    return Mesh(primitive="cuboid", size=size, color=color)


def _inertia(mass: float, size: tuple[float, float, float]) -> tuple[float, float, float]:
    x, y, z = size
    return (mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12, mass * (x * x + y * y) / 12)


def demo_scene() -> Scene:
    floor = SceneObject(
        1,
        "Floor",
        "shape",
        pose=Pose((0.0, 0.0, -0.01)),
        shape=ShapeData((_box((3.0, 3.0, 0.02), (0.82, 0.84, 0.86)),), dynamics=Dynamics()),
    )
    post = SceneObject(
        2,
        "Post",
        "shape",
        pose=Pose((0.0, 0.0, 0.25)),
        model_base=True,
        shape=ShapeData((_box((0.1, 0.1, 0.5), (0.35, 0.38, 0.42)),), dynamics=Dynamics()),
    )
    arm_joint = SceneObject(
        3,
        "ArmJoint",
        "joint",
        parent=2,
        pose=Pose((0.08, 0.0, 0.15), (0.0, math.sqrt(0.5), 0.0, math.sqrt(0.5))),  # axis +x
        joint=JointData(
            "revolute",
            "position",
            minimum=-math.pi,
            range=2 * math.pi,
            motor_enabled=True,
            control_enabled=True,
            max_force=50.0,
            max_velocity=3.0,
            p_gain=0.1,
        ),
    )
    arm_size = (0.3, 0.04, 0.04)  # hangs along the joint frame's x (world -z)
    arm = SceneObject(
        4,
        "Arm",
        "shape",
        parent=3,
        pose=Pose((ARM_RADIUS, 0.0, 0.04)),
        shape=ShapeData(
            (_box(arm_size, (0.85, 0.35, 0.2)),),
            dynamics=Dynamics(static=False, mass=0.5, inertia=_inertia(0.5, arm_size)),
        ),
    )
    flag_joint = SceneObject(
        5,
        "FlagJoint",
        "joint",
        parent=2,
        pose=Pose((0.0, 0.0, 0.27)),
        joint=JointData(
            "revolute",
            "velocity",
            cyclic=True,
            motor_enabled=True,
            max_force=10.0,
        ),
    )
    flag_size = (0.3, 0.02, 0.12)
    flag = SceneObject(
        6,
        "Flag",
        "shape",
        parent=5,
        pose=Pose((0.12, 0.0, 0.08)),
        shape=ShapeData(
            (_box(flag_size, (0.2, 0.45, 0.85)),),
            dynamics=Dynamics(static=False, mass=0.2, inertia=_inertia(0.2, flag_size)),
        ),
    )
    scripts = (
        Script("child", ARM_SCRIPT, object=4),
        Script("child", FLAG_SCRIPT, object=6, threaded=True),
    )
    return Scene(
        (floor, post, arm_joint, arm, flag_joint, flag),
        scripts=scripts,
        source="lua_arm.simscene.xml",
        format="xml",
        version="CoppeliaSim 4.1.0",
    )


def main(argv: list[str] | None = None) -> int:
    from sims.scene.xml_write import write_xml

    args = sys.argv[1:] if argv is None else argv
    text = write_xml(demo_scene())
    if not args:
        sys.stdout.write(text)
        return 0
    with open(args[0], "w", encoding="utf-8", newline="\n") as f:
        f.write(text)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
