"""Reader for CoppeliaSim's XML scene format (``.simscene.xml``, the "simple" XML flavour).

What the file holds (from CoppeliaSim's XML serializers; the file's own comments say the same):
a ``<CoppeliaSim>`` root with ``filetype`` (``simpleScene``/``simpleModel``), ``prgVer``
(e.g. 40100), scene settings (``dynamics/gravity``, ``simulation/simulationTimeStep``) and the
object tree: ``shape``, ``joint``, ``dummy``, ``camera``, ``light``, ``proximitySensor``,
``visionSensor``, ``forceSensor``, ``graph``, ``path``, ``ocTree``, ``pointCloud``, ``script``
elements, a child element being a child object. Every object has ``common`` (``name``,
``altName``, 4.2+ ``alias``, ``localFrame`` with ``position`` and ``euler`` in degrees, or
``quaternion`` (w x y z); ``switches/modelBase``; ``layer``) and may carry a ``childScript`` or
``customizationScript`` (``scriptText``, ``switches/enabled``). Linear values are metres, angles
degrees, colours 0-255.

Shapes hold a ``primitive`` (``type``, ``size``, ``localFrame``, ``color/ambientDiffuse``), a
``mesh`` (inline ``vertices``/``indices`` in its ``localFrame``, or an external ``fileName``, not
read and listed in the notes), a ``heightfield`` or a ``compound`` of those; ``dynamics`` has
``mass``, ``localInertiaFrame`` + ``principalMomentOfInertia`` (divided by the mass, as the
FANUC scene's 1000 kg floor shows) or ``centerOfMass`` + ``inertiaMatrix`` (times the mass),
``switches/static``, ``switches/respondable``, ``respondableMask`` and the material's Bullet
friction. The file has no handles: objects are numbered in document order from 0.

Parsing is safe: a document type declaration or entity definition is refused before anything is
expanded, and loading runs nothing.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import replace
from xml.parsers import expat as pyexpat

from sims.scene.errors import SceneError
from sims.scene.limits import (
    MAX_DEPTH,
    MAX_XML_ITEMS,
    LimitError,
    MeshBudget,
    check_object_count,
)
from sims.scene.model import (
    CameraData,
    DummyData,
    Dynamics,
    ForceSensorData,
    JointData,
    LightData,
    ProximitySensorData,
    Scene,
    SceneNote,
    SceneObject,
    Script,
    ShapeData,
    VisionSensorData,
)
from sims.scene.xml_shapes import read_dynamics, read_geometry, read_physics
from sims.scene.xml_values import flag, floats, frame, number, text

OBJECT_TAGS = {
    "shape": "shape",
    "joint": "joint",
    "dummy": "dummy",
    "camera": "camera",
    "light": "light",
    "proximitySensor": "proximity_sensor",
    "visionSensor": "vision_sensor",
    "forceSensor": "force_sensor",
    "graph": "graph",
    "path": "path",
    "ocTree": "octree",
    "pointCloud": "point_cloud",
    "script": "unknown",
}
XML_LINK_TYPES = {
    "dynamics_loopClosure": "dynamics_loop_closure",
    "dynamics_forceConstraint": "dynamics_force_constraint",
    "ik_tipTarget": "ik_tip_target",
    "dynamics_tendon": "dynamics_tendon",
    "default": "",
}
PROX_TYPES = {"pyramid", "cylinder", "disc", "cone", "ray"}
SETTINGS_TAGS = {"filetype", "xmlSerializationNb", "prgFlavor", "prgVer", "prgRev", "environment",
                 "settings", "dynamics", "simulation"}  # fmt: skip


class _Refuse(Exception):
    pass


def parse(data: bytes, source: str) -> ET.Element:
    """Parse with expat into an ElementTree, refusing DTDs and entity declarations (so no entity
    is ever expanded) and never fetching anything."""
    builder = ET.TreeBuilder()
    expat = pyexpat.ParserCreate()
    expat.buffer_text = True

    def refuse(*_args: object) -> None:
        raise _Refuse()

    expat.StartDoctypeDeclHandler = refuse
    expat.EntityDeclHandler = refuse
    expat.UnparsedEntityDeclHandler = refuse
    expat.ExternalEntityRefHandler = refuse
    items = [0]

    def start(tag: str, attrs: dict[str, str]) -> object:
        items[0] += 1 + len(attrs)
        if items[0] > MAX_XML_ITEMS:
            raise LimitError(
                f"more than {MAX_XML_ITEMS:,} XML elements and attributes (the course's XML "
                "scene has 2,267)"
            )
        return builder.start(tag, attrs)

    expat.StartElementHandler = start
    expat.EndElementHandler = builder.end
    expat.CharacterDataHandler = builder.data
    try:
        expat.Parse(data, True)
        return builder.close()
    except LimitError as exc:
        raise SceneError(source, f"line {expat.CurrentLineNumber}", str(exc)) from None
    except _Refuse:
        line = expat.CurrentLineNumber
        raise SceneError(
            source, f"line {line}", "document type or entity declarations are not allowed"
        ) from None
    except pyexpat.ExpatError as exc:
        raise SceneError(
            source, f"line {exc.lineno}", f"not well-formed XML: {pyexpat.ErrorString(exc.code)}"
        ) from None
    except AssertionError:  # TreeBuilder: no root element
        raise SceneError(source, "line 1", "no XML element in the file") from None


def read_xml(data: bytes, source: str) -> Scene:
    root = parse(data, source)
    if root.tag != "CoppeliaSim":
        raise SceneError(source, "file", f"root element is <{root.tag}>, not <CoppeliaSim>")
    filetype = text(root, "filetype", "")
    if filetype not in ("simpleScene", "simpleModel"):
        raise SceneError(
            source, "file", f"filetype {filetype!r} not understood (simpleScene/simpleModel)"
        )
    program = int(number(root, "prgVer", 0))
    reader = _Reader(source, program)
    try:
        gravity = floats(root, "dynamics/gravity", 3) or (0.0, 0.0, -9.81)
        time_step = number(root, "simulation/simulationTimeStep", 0.05)
        physics = read_physics(root.find("dynamics"))
    except ValueError as exc:
        raise SceneError(source, "settings", str(exc)) from None
    for child in root:
        if child.tag in OBJECT_TAGS:
            reader.tree(child)
        elif child.tag not in SETTINGS_TAGS:
            reader.notes.append(SceneNote("file", f"element <{child.tag}> not understood, skipped"))
    reader.resolve_links()
    version = f"XML, CoppeliaSim {program // 10000}.{program // 100 % 100}.{program % 100}"
    return Scene(
        objects=tuple(reader.objects),
        scripts=tuple(reader.scripts),
        source=source,
        format="xml",
        version=version,
        gravity=gravity,  # type: ignore[arg-type]
        notes=tuple(reader.notes),
        time_step=time_step,
        physics=physics,
    )


class _Reader:
    def __init__(self, source: str, program: int):
        self.source = source
        self.program = program
        self.objects: list[SceneObject] = []
        self.scripts: list[Script] = []
        self.notes: list[SceneNote] = []
        self.links: dict[int, str] = {}  # dummy handle -> name of the dummy it is linked to
        self.budget = MeshBudget()

    def resolve_links(self) -> None:
        """``linkedDummy`` names a dummy (by name or alias): turn it into its handle."""
        by_name = {o.name: o.handle for o in self.objects if o.kind == "dummy"}
        by_name.update({o.alias: o.handle for o in self.objects if o.kind == "dummy" and o.alias})
        for i, obj in enumerate(self.objects):
            if obj.handle in self.links and obj.dummy is not None:
                target = by_name.get(self.links[obj.handle])
                if target is None:
                    self.notes.append(
                        SceneNote(obj.name, f"linked dummy {self.links[obj.handle]!r} not found")
                    )
                    continue
                self.objects[i] = replace(obj, dummy=replace(obj.dummy, linked_to=target))

    def tree(self, top: ET.Element) -> None:
        """A top-level object and everything below it, in document order, without recursion
        (a file may nest objects thousands deep: that is an error past ``MAX_DEPTH``)."""
        stack: list[tuple[ET.Element, int | None, int]] = [(top, None, 0)]
        while stack:
            el, parent, depth = stack.pop()
            if depth > MAX_DEPTH:
                name = text(el.find("common"), "name") or el.tag
                raise SceneError(
                    self.source,
                    name,
                    f"objects nested more than {MAX_DEPTH} deep (course scenes nest 24 at most)",
                )
            try:
                check_object_count(len(self.objects) + 1)
            except LimitError as exc:
                raise SceneError(self.source, "file", str(exc)) from None
            handle = self.object(el, parent)
            kids = [child for child in el if child.tag in OBJECT_TAGS]
            stack.extend((child, handle, depth + 1) for child in reversed(kids))

    def object(self, el: ET.Element, parent: int | None) -> int:
        """Read one object element (not its children); returns its handle."""
        handle = len(self.objects)
        common = el.find("common")
        name = text(common, "name") or f"{el.tag}{handle}"
        try:
            obj = self._object(el, common, handle, name, parent)
        except ValueError as exc:  # LimitError included: its message says which bound
            raise SceneError(self.source, name, str(exc)) from None
        self.objects.append(obj)
        for tag, kind in (("childScript", "child"), ("customizationScript", "customization")):
            for script in el.findall(tag):
                self.scripts.append(
                    Script(
                        kind=kind,
                        text=_raw_text(script, "scriptText"),
                        object=handle,
                        threaded=flag(script, "switches/threadedExecution", False),
                        disabled=not flag(script, "switches/enabled", True),
                    )
                )
        return handle

    def _object(self, el, common, handle: int, name: str, parent: int | None) -> SceneObject:
        kind = OBJECT_TAGS[el.tag]
        extra: dict[str, object] = {}
        if kind == "shape":
            extra["shape"] = self._shape(el, name)
        elif kind == "joint":
            extra["joint"] = _joint(el)
        elif kind == "proximity_sensor":
            extra["proximity_sensor"] = _proximity(el)
        elif kind == "vision_sensor":
            extra["vision_sensor"] = _vision(el)
        elif kind == "force_sensor":
            extra["force_sensor"] = _force_sensor(el)
        elif kind == "camera":
            extra["camera"] = _camera(el)
        elif kind == "light":
            extra["light"] = _light(el)
        elif kind == "dummy":
            link = text(el, "linkType", "") or ""
            extra["dummy"] = DummyData(link_type=XML_LINK_TYPES.get(link, link))
            if text(el, "linkedDummy"):
                self.links[handle] = text(el, "linkedDummy") or ""
        else:
            self.notes.append(SceneNote(name, f"<{el.tag}> objects are not simulated"))
        layer = int(number(common, "layer", 1))
        return SceneObject(
            handle=handle,
            name=name,
            kind=kind,
            parent=parent,
            pose=frame(common.find("localFrame") if common is not None else None),
            alias=text(common, "alias", "") or "",
            visible=bool(layer & 0xFF),
            model_base=flag(common, "switches/modelBase", False),
            detectable=_detectable(common),
            **extra,  # type: ignore[arg-type]
        )

    def _shape(self, el: ET.Element, name: str) -> ShapeData:
        local: list[str] = []
        meshes, compound = read_geometry(el, local)
        self.budget.take(sum(len(m.vertices) + len(m.indices) for m in meshes))
        dynamics: Dynamics = read_dynamics(el.find("dynamics"), self.program)
        self.notes.extend(SceneNote(name, m) for m in local)
        if not meshes:
            self.notes.append(SceneNote(name, "shape without primitive, mesh or compound"))
        return ShapeData(meshes=tuple(meshes), compound=compound, dynamics=dynamics)


def _raw_text(el: ET.Element, path: str) -> str:
    """An element's text exactly as written (script text keeps its white space)."""
    node = el.find(path)
    return node.text or "" if node is not None else ""


def _joint(el: ET.Element) -> JointData:
    kind = text(el, "type", "revolute") or "revolute"
    if kind not in ("revolute", "prismatic", "spherical"):
        raise ValueError(f"joint type {kind!r} not understood")
    k = math.pi / 180.0 if kind == "revolute" else 1.0
    mode_text = text(el, "mode", "passive") or "passive"
    dyn = el.find("dynamics")
    v: dict[str, object] = {
        "kind": kind,
        "cyclic": flag(el, "switches/cyclic", False) and kind == "revolute",
        "minimum": number(el, "minPosition", 0.0) * k,
        "range": number(el, "range", 0.0) * k,
        "position": number(el, "position", 0.0) * k,
        "target": number(el, "targetPosition", number(dyn, "targetPosition", 0.0)) * k,
        "target_velocity": number(el, "targetVelocity", number(dyn, "targetVelocity", 0.0)) * k,
        "max_force": abs(number(dyn, "maxForce", 0.0)),
    }
    upper = floats(dyn, "upperVelocityLimit", 1) or floats(el, "maxVelAccelJerk", 3)
    if upper:
        v["max_velocity"] = upper[0] * k
    pid = floats(dyn, "pidValues", 3)
    if pid:
        v["p_gain"], v["i_gain"], v["d_gain"] = pid
    kc = floats(dyn, "kcValues", 2)
    if kc:
        v["spring_k"], v["spring_c"] = kc
    sq = floats(el, "sphericalQuaternion", 4)  # CoppeliaSim order: w x y z
    if sq is not None and kind == "spherical":
        norm = math.sqrt(sum(q * q for q in sq)) or 1.0
        v["spherical_rotation"] = (sq[1] / norm, sq[2] / norm, sq[3] / norm, sq[0] / norm)
    dep = el.find("dependency")
    if dep is not None:
        v["offset"] = number(dep, "offset_m_or_rad", 0.0)
        v["coefficient"] = number(dep, "mult_m_or_rad", 1.0)
    motor = flag(dyn, "switches/motorEnabled", False)
    ctrl = flag(dyn, "switches/controlLoopEnabled", False)
    spring = flag(dyn, "switches/springMode", False)
    ctrl_mode = text(dyn, "ctrlMode")
    if mode_text in ("force", "dynamic") or flag(el, "switches/hybridMode", False):
        if ctrl_mode is not None:
            mode = {"0": "velocity", "2": "velocity", "3": "position", "4": "spring"}.get(
                ctrl_mode, "position"
            )
            motor, ctrl = ctrl_mode != "0", mode in ("position", "spring")
        elif not motor:
            mode = "velocity"  # with motor_enabled False: turns freely
        else:
            mode = "velocity" if not ctrl else ("spring" if spring else "position")
    elif mode_text == "dependent":
        mode = "dependent"
    elif mode_text == "ik":
        mode = "ik"
    elif mode_text in ("passive", "kinematic"):
        mode = "passive"
    else:
        raise ValueError(f"joint mode {mode_text!r} not understood")
    return JointData(mode=mode, motor_enabled=motor, control_enabled=ctrl, **v)  # type: ignore[arg-type]


def _proximity(el: ET.Element) -> ProximitySensorData:
    kind = text(el, "type", "ray") or "ray"
    if kind not in PROX_TYPES:
        raise ValueError(f"proximity sensor type {kind!r} not understood")
    vol = el.find("volume")
    if flag(el, "randomizedDetection/enabled", False) and kind == "ray":
        kind = "randomized_ray"
    far = floats(vol, "xySizeFar", 2) or (0.0, 0.0)
    radii = floats(vol, "closeFarRadius", 2) or (0.0, 0.0)
    return ProximitySensorData(
        volume=kind,
        range=number(vol, "range", 0.1),
        offset=number(vol, "offset", 0.0),
        angle=math.radians(number(vol, "angle", 0.0)),
        size=far if kind == "pyramid" else (2 * radii[0], 2 * radii[1]),  # type: ignore[arg-type]
        explicit=flag(el, "switches/explicitHandling", False),
    )


def _vision(el: ET.Element) -> VisionSensorData:
    res = floats(el, "resolution", 2) or (32, 32)
    clip = floats(el, "clippingPlanes", 2) or (0.01, 10.0)
    return VisionSensorData(
        resolution=(int(res[0]), int(res[1])),
        view_angle=math.radians(number(el, "viewAngle", 60.0)),
        near=clip[0],
        far=clip[1],
        perspective=flag(el, "switches/perspectiveMode", True),
        ortho_size=number(el, "orthoViewSize", 1.0),
    )


def _camera(el: ET.Element) -> CameraData:
    clip = floats(el, "clippingPlanes", 2) or (0.05, 30.0)
    return CameraData(
        view_angle=math.radians(number(el, "viewAngle", 60.0)),
        near=clip[0],
        far=clip[1],
        perspective=flag(el, "switches/perspectiveMode", True),
    )


def _light(el: ET.Element) -> LightData:
    kind = text(el, "type", "omni") or "omni"
    kinds = {
        "omnidirectional": "omni",
        "omni": "omni",
        "spot": "spot",
        "directional": "directional",
    }
    if kind not in kinds:
        raise ValueError(f"light type {kind!r} not understood")
    rgb = floats(el, "color/light/ambientDiffuse", 3) or (128, 128, 128)
    return LightData(
        kind=kinds[kind],
        enabled=flag(el, "switches/lightIsActive", True),
        diffuse=tuple(min(1.0, c / 255.0) for c in rgb),  # type: ignore[arg-type]
    )


def _force_sensor(el: ET.Element) -> ForceSensorData:
    force = floats(el, "force/threshold", 1)
    torque = floats(el, "torque/threshold", 1)
    return ForceSensorData(
        filter_samples=int(number(el, "filter/sampleSize", 1)),
        force_threshold=force[0] if force and flag(el, "force/thresholdEnabled", False) else None,
        torque_threshold=torque[0]
        if torque and flag(el, "torque/thresholdEnabled", False)
        else None,
    )


DETECTABLE_TAGS = (
    "detectable",
    "ultrasonicDetectable",
    "infraredDetectable",
    "laserDetectable",
    "inductiveDetectable",
    "capacitiveDetectable",
)


def _detectable(common: ET.Element | None) -> bool:
    """Whether proximity sensors see the object: any detectable flag of its special properties
    (an object that does not say is detectable, as CoppeliaSim's shapes are by default)."""
    props = common.find("localObjectSpecialProperty") if common is not None else None
    if props is None or not any(props.find(t) is not None for t in DETECTABLE_TAGS):
        return True
    return any(flag(props, t, False) for t in DETECTABLE_TAGS)
