"""Write a scene model as CoppeliaSim's simple XML scene format (``.simscene.xml``).

Why: a course scene (``.ttt``) can become a plain-text scene the project ships and diffs (saying
where it came from), and the XML reader is checked by reading back what this writes. The output
uses the tags :mod:`sims.scene.xml` reads (the ones CoppeliaSim's own simple XML writer uses):
lengths in metres, angles in degrees (Euler ``Rx Ry Rz``), colours 0-255, principal moments of
inertia divided by the mass. Numbers are written with ``repr`` so that a write/read round trip
keeps every float; output is deterministic (same model, same bytes). The main script is not
written (CoppeliaSim's simple format has none); child and customization scripts are.
"""

from __future__ import annotations

import math
from xml.sax.saxutils import escape

from sims.scene.model import Mesh, Pose, Scene, SceneObject, Script
from sims.scene.rotations import euler_degrees

TAGS = {
    "shape": "shape",
    "joint": "joint",
    "dummy": "dummy",
    "camera": "camera",
    "light": "light",
    "proximity_sensor": "proximitySensor",
    "vision_sensor": "visionSensor",
    "force_sensor": "forceSensor",
}
LIGHT_TYPES = {"omni": "omnidirectional", "spot": "spot", "directional": "directional"}


def _n(v: float) -> str:
    v = float(v)
    return "0" if v == 0 else repr(v)


def _ns(vals) -> str:
    return " ".join(_n(v) for v in vals)


class _Out:
    def __init__(self) -> None:
        self.lines: list[str] = []
        self.depth = 0

    def open(self, tag: str) -> None:
        self.lines.append(f"{'    ' * self.depth}<{tag}>")
        self.depth += 1

    def close(self, tag: str) -> None:
        self.depth -= 1
        self.lines.append(f"{'    ' * self.depth}</{tag}>")

    def leaf(self, tag: str, value: object) -> None:
        if isinstance(value, bool):
            value = "true" if value else "false"
        self.lines.append(f"{'    ' * self.depth}<{tag}>{escape(str(value))}</{tag}>")

    def frame(self, tag: str, pose: Pose) -> None:
        self.open(tag)
        self.leaf("position", _ns(pose.position))
        self.leaf("euler", _ns(euler_degrees(pose.quaternion)))
        self.close(tag)


def write_xml(scene: Scene) -> str:
    out = _Out()
    out.open("CoppeliaSim")
    out.leaf("filetype", "simpleScene")
    out.leaf("xmlSerializationNb", 1)
    out.leaf("prgVer", 40100)
    out.open("dynamics")
    out.leaf("gravity", _ns(scene.gravity))
    out.close("dynamics")
    out.open("simulation")
    out.leaf("simulationTimeStep", _n(scene.time_step))
    out.close("simulation")
    handles = {o.handle for o in scene.objects}
    scripts: dict[int, list[Script]] = {}
    for script in scene.scripts:
        if script.object is not None and script.kind in ("child", "customization"):
            scripts.setdefault(script.object, []).append(script)
    written: set[int] = set()
    for obj in scene.objects:
        if obj.parent is None or obj.parent not in handles:
            _tree(out, scene, obj, scripts, written)
    out.close("CoppeliaSim")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + "\n".join(out.lines) + "\n"


def _tree(
    out: _Out, scene: Scene, top: SceneObject, scripts: dict[int, list[Script]], written: set[int]
) -> None:
    """``top`` and the objects below it, each inside its parent's element, without recursion
    (children from the scene's index: linear in the objects)."""
    stack: list[SceneObject | str] = [top]
    while stack:
        item = stack.pop()
        if isinstance(item, str):
            out.close(item)
            continue
        if id(item) in written:
            continue
        written.add(id(item))
        tag = _object(out, scene, item, scripts.get(item.handle, ()))
        stack.append(tag)
        stack.extend(reversed(scene.children(item.handle)))


def _object(out: _Out, scene: Scene, obj: SceneObject, scripts) -> str:
    """Open the object's element and write its own content; returns the tag to close."""
    tag = TAGS.get(obj.kind, "dummy")  # kinds without a simple-XML form keep their place
    out.open(tag)
    out.open("common")
    out.leaf("name", obj.name)
    if obj.alias:
        out.leaf("alias", obj.alias)
    out.frame("localFrame", obj.pose)
    out.leaf("layer", 1 if obj.visible else 256)
    out.open("switches")
    out.leaf("modelBase", obj.model_base)
    out.close("switches")
    out.close("common")
    if obj.shape is not None:
        _shape(out, obj)
    elif obj.joint is not None:
        _joint(out, obj)
    elif obj.proximity_sensor is not None:
        _proximity(out, obj)
    elif obj.vision_sensor is not None:
        v = obj.vision_sensor
        out.leaf("resolution", f"{v.resolution[0]} {v.resolution[1]}")
        out.leaf("clippingPlanes", _ns((v.near, v.far)))
        out.leaf("viewAngle", _n(math.degrees(v.view_angle)))
        out.leaf("orthoViewSize", _n(v.ortho_size))
        out.open("switches")
        out.leaf("perspectiveMode", v.perspective)
        out.close("switches")
    elif obj.camera is not None:
        c = obj.camera
        out.leaf("viewAngle", _n(math.degrees(c.view_angle)))
        out.leaf("clippingPlanes", _ns((c.near, c.far)))
        out.open("switches")
        out.leaf("perspectiveMode", c.perspective)
        out.close("switches")
    elif obj.light is not None:
        light = obj.light
        out.leaf("type", LIGHT_TYPES[light.kind])
        out.open("switches")
        out.leaf("lightIsActive", light.enabled)
        out.close("switches")
        out.open("color")
        out.open("light")
        out.leaf("ambientDiffuse", " ".join(str(round(c * 255)) for c in light.diffuse))
        out.close("light")
        out.close("color")
    elif obj.force_sensor is not None:
        _force_sensor(out, obj)
    elif obj.dummy is not None:
        names = {"dynamics_loop_closure": "dynamics_loopClosure",
                 "dynamics_force_constraint": "dynamics_forceConstraint",
                 "ik_tip_target": "ik_tipTarget", "dynamics_tendon": "dynamics_tendon",
                 "": "default"}  # fmt: skip
        out.leaf("linkType", names.get(obj.dummy.link_type, obj.dummy.link_type))
        linked = (
            scene.by_handle().get(obj.dummy.linked_to) if obj.dummy.linked_to is not None else None
        )
        if linked is not None:
            out.leaf("linkedDummy", linked.name)
    for script in scripts:
        tag_s = "childScript" if script.kind == "child" else "customizationScript"
        out.open(tag_s)
        out.open("switches")
        out.leaf("enabled", not script.disabled)
        out.leaf("threadedExecution", script.threaded)
        out.close("switches")
        out.leaf("scriptText", script.text)
        out.close(tag_s)
    return tag


def _mesh(out: _Out, mesh: Mesh) -> None:
    if mesh.primitive is not None:
        out.open("primitive")
        out.leaf("type", mesh.primitive)
        out.leaf("size", _ns(mesh.size))
    else:
        out.open("mesh")
        out.leaf("vertices", _ns(mesh.vertices))
        out.leaf("indices", " ".join(str(i) for i in mesh.indices))
    out.frame("localFrame", mesh.local)
    out.open("color")
    out.leaf("ambientDiffuse", " ".join(str(round(c * 255)) for c in mesh.color))
    out.close("color")
    out.close("primitive" if mesh.primitive is not None else "mesh")


def _shape(out: _Out, obj: SceneObject) -> None:
    shape = obj.shape
    assert shape is not None
    if shape.compound or len(shape.meshes) != 1:
        out.open("compound")
        for mesh in shape.meshes:
            _mesh(out, mesh)
        out.close("compound")
    else:
        _mesh(out, shape.meshes[0])
    d = shape.dynamics
    out.open("dynamics")
    out.leaf("respondableMask", d.respondable_mask)
    out.leaf("mass", _n(d.mass))
    out.frame("localInertiaFrame", d.inertia_frame)
    out.leaf("principalMomentOfInertia", _ns(i / d.mass for i in d.inertia))
    out.open("switches")
    out.leaf("static", d.static)
    out.leaf("respondable", d.respondable)
    out.close("switches")
    if d.friction is not None:
        out.open("material")
        out.open("engines")
        out.open("bullet")
        out.leaf("friction", _n(d.friction))
        out.leaf("oldfriction", _n(d.friction))
        out.close("bullet")
        out.close("engines")
        out.close("material")
    out.close("dynamics")


def _joint(out: _Out, obj: SceneObject) -> None:
    j = obj.joint
    assert j is not None
    k = 180.0 / math.pi if j.kind == "revolute" else 1.0
    torque_mode = j.mode in ("position", "velocity", "spring")
    out.leaf("type", j.kind)
    out.leaf("mode", "force" if torque_mode else j.mode)
    out.leaf("minPosition", _n(j.minimum * k))
    out.leaf("range", _n(j.range * k))
    out.leaf("position", _n(j.position * k))
    if j.kind == "spherical":
        x, y, z, w = j.spherical_rotation
        out.leaf("sphericalQuaternion", _ns((w, x, y, z)))
    out.open("switches")
    out.leaf("cyclic", j.cyclic)
    out.close("switches")
    if j.mode == "dependent":
        out.open("dependency")
        out.leaf("offset_m_or_rad", _n(j.offset))
        out.leaf("mult_m_or_rad", _n(j.coefficient))
        out.close("dependency")
    out.open("dynamics")
    out.leaf("maxForce", _n(j.max_force))
    if j.max_velocity is not None:
        out.leaf("upperVelocityLimit", _n(j.max_velocity * k))
    out.leaf("targetPosition", _n(j.target * k))
    out.leaf("targetVelocity", _n(j.target_velocity * k))
    out.leaf("pidValues", _ns((j.p_gain, j.i_gain, j.d_gain)))
    out.leaf("kcValues", _ns((j.spring_k, j.spring_c)))
    out.open("switches")
    out.leaf("motorEnabled", j.motor_enabled)
    out.leaf("controlLoopEnabled", j.control_enabled)
    out.leaf("springMode", j.mode == "spring")
    out.close("switches")
    out.close("dynamics")


def _proximity(out: _Out, obj: SceneObject) -> None:
    s = obj.proximity_sensor
    assert s is not None
    randomized = s.volume == "randomized_ray"
    out.leaf("type", "ray" if randomized else s.volume)
    out.open("volume")
    out.leaf("offset", _n(s.offset))
    out.leaf("range", _n(s.range))
    if s.volume == "pyramid":
        out.leaf("xySizeFar", _ns(s.size))
    else:
        out.leaf("closeFarRadius", _ns((s.size[0] / 2, s.size[1] / 2)))
    out.leaf("angle", _n(math.degrees(s.angle)))
    out.close("volume")
    if s.explicit:
        out.open("switches")
        out.leaf("explicitHandling", True)
        out.close("switches")
    if randomized:
        out.open("randomizedDetection")
        out.leaf("enabled", True)
        out.close("randomizedDetection")


def _force_sensor(out: _Out, obj: SceneObject) -> None:
    f = obj.force_sensor
    assert f is not None
    out.open("filter")
    out.leaf("sampleSize", f.filter_samples)
    out.close("filter")
    for tag, value in (("force", f.force_threshold), ("torque", f.torque_threshold)):
        out.open(tag)
        out.leaf("thresholdEnabled", value is not None)
        out.leaf("threshold", _n(value or 0.0))
        out.close(tag)
