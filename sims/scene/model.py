"""The scene model: what a CoppeliaSim scene file holds, as plain frozen data.

This is the contract between the scene *readers* (``sims/scene/ttt.py`` for the binary ``.ttt``
format, ``sims/scene/xml.py`` for ``.simscene.xml``) and the scene *builder* that turns a model
into a pybullet world (``sims/scene/build.py``). Readers never import pybullet; the builder never
looks at file bytes. Loading a scene runs nothing: scripts are carried as text.

Conventions (CoppeliaSim's own, kept so that a script sees what it would see in CoppeliaSim):
- lengths in metres, angles in radians, masses in kg, colours as RGB floats 0..1;
- every pose is *local*: relative to the parent object's frame (world frame for top-level objects);
- quaternions are (x, y, z, w);
- ``handle`` is the object's id as saved in the file (unique in the file, not necessarily dense;
  XML files save none: their objects are numbered 0, 1, 2 ... in document order).
- a rotation (quaternion or XML Euler angles) maps child-frame coordinates to parent-frame ones:
  ``p_parent = R p_child + t``. CoppeliaSim's Euler angles (alpha, beta, gamma; degrees in XML)
  are ``R = Rx(alpha) Ry(beta) Rz(gamma)``; ``.ttt`` files store quaternions as (w, x, y, z) and
  the readers reorder them to (x, y, z, w).
- mesh vertices are in the mesh's ``local`` frame, itself given in the shape's frame.
- a joint's children hang from the joint frame *moved by the joint's position* (as in
  CoppeliaSim): turned by ``position`` about z (revolute), shifted by it along z (prismatic),
  turned by ``spherical_rotation`` (spherical). Their ``pose`` is relative to that moved frame.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from types import MappingProxyType

from sims.scene.model_mech import IkElement as IkElement  # re-exported: part of the model
from sims.scene.model_mech import IkGroup as IkGroup
from sims.scene.model_mech import PathData as PathData
from sims.scene.model_mech import PathPoint as PathPoint
from sims.scene.model_mech import Physics as Physics

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]
RGB = tuple[float, float, float]
IDENTITY: Quat = (0.0, 0.0, 0.0, 1.0)


@dataclass(frozen=True)
class Pose:
    position: Vec3 = (0.0, 0.0, 0.0)
    quaternion: Quat = IDENTITY


@dataclass(frozen=True)
class TextureImage:
    """A texture object: ``rgba`` holds width x height x 4 bytes, the first row at v = 0."""

    id: int
    name: str
    width: int
    height: int
    rgba: bytes = field(repr=False)


@dataclass(frozen=True)
class TextureMapping:
    """How one mesh wears a texture (see :mod:`sims.scene.textures`). ``coordinates``: fixed texture
    coordinates (u, v per triangle corner), empty when the mapping computes them. ``image``:
    the texture object, filled in once the whole file is read (None if the file lacks it)."""

    texture: int
    mode: str = "plane"
    scaling: tuple[float, float] = (1.0, 1.0)
    pose: Pose = field(default_factory=Pose)
    repeat_u: bool = False
    repeat_v: bool = False
    interpolate: bool = False
    apply: str = "modulate"
    coordinates: tuple[float, ...] = field(default=(), repr=False)
    image: TextureImage | None = None


@dataclass(frozen=True)
class Mesh:
    """One mesh of a shape, in the shape's frame: flat vertex list (x, y, z, ...) and triangle
    indices (i, j, k, ...). ``primitive`` names the pure type when the mesh is a primitive
    ("cuboid", "cylinder", "sphere", "disc", "cone", "plane"), with its ``size`` (x, y, z extents;
    for a sphere/cylinder the diameters in x and y and the height in z); None for a plain mesh.
    ``local`` is the mesh's pose in the shape frame (compound shapes place their parts).
    ``wireframe``: CoppeliaSim draws only the mesh's edges (a floor's outline, say); sitegen's
    renderers draw triangles only, so such a mesh is not drawn."""

    vertices: tuple[float, ...] = ()
    indices: tuple[int, ...] = ()
    primitive: str | None = None
    size: Vec3 = (0.0, 0.0, 0.0)
    local: Pose = field(default_factory=Pose)
    color: RGB = (0.8, 0.8, 0.8)  # ambient/diffuse colour
    visible: bool = True
    wireframe: bool = False
    convex: bool | None = None  # CoppeliaSim's own flag (None: the file does not say)
    texture: TextureMapping | None = None  # its texture and how it is mapped, if any
    opacity: float = 1.0  # below 1: CoppeliaSim draws it translucent (sensors see through it)


@dataclass(frozen=True)
class Dynamics:
    """A shape's physical properties. ``static`` shapes do not move under physics;
    ``respondable`` shapes collide. ``inertia`` is the principal moments in kg·m² (both file
    formats store them divided by the mass; the readers multiply by ``mass``) and
    ``inertia_frame`` their frame in the shape frame: its position is the centre of mass.
    ``friction`` is the Bullet 2.78 friction coefficient the scene was saved with (CoppeliaSim's
    default engine for these scenes), None when the file does not say."""

    static: bool = True
    respondable: bool = True
    mass: float = 1.0
    inertia: Vec3 = (1e-3, 1e-3, 1e-3)
    inertia_frame: Pose = field(default_factory=Pose)
    friction: float | None = None
    respondable_mask: int = 0xFFFF


@dataclass(frozen=True)
class ShapeData:
    meshes: tuple[Mesh, ...] = ()
    compound: bool = False
    dynamics: Dynamics = field(default_factory=Dynamics)


@dataclass(frozen=True)
class JointData:
    """``kind``: "revolute", "prismatic" or "spherical". ``mode``: "passive" (CoppeliaSim's
    passive/kinematic mode: under physics the joint holds its position, only scripts move it),
    "position" (position control: ``target``, ``p_gain``/``i_gain``/``d_gain``, ``max_force``,
    ``max_velocity``), "velocity" (``target_velocity``, ``max_force``; with ``motor_enabled``
    False it is a torque/force-mode joint with its motor off: it turns freely), "spring"
    (spring-damper: ``spring_k``, ``spring_c``), "ik" or "dependent" (``dependent_on`` handle,
    ``offset``, ``coefficient``). ``cyclic`` revolute joints have no range; otherwise
    [``minimum``, ``minimum + range``]. ``position`` is the saved (initial) position. The joint
    axis is the joint frame's z axis, as in CoppeliaSim."""

    kind: str = "revolute"
    mode: str = "passive"
    cyclic: bool = False
    minimum: float = 0.0
    range: float = 0.0
    position: float = 0.0
    motor_enabled: bool = False
    control_enabled: bool = False
    target: float = 0.0
    target_velocity: float = 0.0
    max_force: float = 0.0
    max_velocity: float | None = None
    p_gain: float = 0.1
    i_gain: float = 0.0
    d_gain: float = 0.0
    spring_k: float = 0.0
    spring_c: float = 0.0
    dependent_on: int | None = None
    offset: float = 0.0
    coefficient: float = 1.0
    screw_pitch: float = 0.0
    ik_weight: float = 1.0  # how much IK moves this joint (0: not at all)
    hybrid: bool = False  # IK sets its position target, the motor drives it (dynamic IK)
    spherical_rotation: Quat = IDENTITY  # a spherical joint's saved position


@dataclass(frozen=True)
class ProximitySensorData:
    """``volume``: "ray", "randomized_ray", "pyramid", "cylinder", "disc", "cone". The sensor
    looks along its frame's +z. ``range`` is the far distance, ``offset`` the near distance,
    ``angle`` the full opening angle (cone/disc), ``size`` x/y extents where relevant.
    ``explicit``: explicit handling; CoppeliaSim's main script then leaves the sensor to the
    scripts (sim.handleProximitySensor) instead of handling it every pass."""

    volume: str = "ray"
    range: float = 0.1
    offset: float = 0.0
    angle: float = 0.0
    size: tuple[float, float] = (0.0, 0.0)
    detect_all: bool = False
    explicit: bool = False


@dataclass(frozen=True)
class VisionSensorData:
    """Looks along its frame's +z, image x to the frame's +x... as CoppeliaSim does.
    ``view_angle`` is the full perspective angle; ``ortho_size`` set when orthographic."""

    resolution: tuple[int, int] = (32, 32)
    view_angle: float = 1.0471975512  # 60°
    near: float = 0.01
    far: float = 10.0
    perspective: bool = True
    ortho_size: float = 1.0


@dataclass(frozen=True)
class DummyData:
    """A dummy's link to another dummy: ``linked_to`` its handle (None: not linked), and
    ``link_type``: "dynamics_loop_closure" (the two dummies are held together by the physics:
    closes kinematic loops), "dynamics_force_constraint", "ik_tip_target", "gcs_loop_closure",
    "gcs_tip", "gcs_target", "dynamics_tendon", "assembly", or "" (none/default)."""

    linked_to: int | None = None
    link_type: str = ""
    follows_path: bool = False  # 3.x: placed on its parent path at its position + ``path_offset``
    path_offset: float = 0.0
    free_on_path: bool = False  # ... at the path point nearest to it instead


@dataclass(frozen=True)
class ForceSensorData:
    filter_samples: int = 1
    force_threshold: float | None = None
    torque_threshold: float | None = None


@dataclass(frozen=True)
class CameraData:
    view_angle: float = 1.0471975512
    near: float = 0.05
    far: float = 30.0
    perspective: bool = True


@dataclass(frozen=True)
class LightData:
    kind: str = "omni"  # "omni", "spot", "directional"
    enabled: bool = True
    diffuse: RGB = (0.5, 0.5, 0.5)


@dataclass(frozen=True)
class Script:
    """An embedded Lua script. ``kind``: "main", "child", "customization". ``threaded`` for
    threaded child scripts. ``object`` is the handle the script is attached to (None: main)."""

    kind: str
    text: str
    object: int | None = None
    threaded: bool = False
    disabled: bool = False


@dataclass(frozen=True)
class SceneObject:
    """One object of the scene tree. ``kind``: "shape", "joint", "dummy", "proximity_sensor",
    "vision_sensor", "force_sensor", "camera", "light", "graph", "path", "octree",
    "point_cloud", "mirror", "mill", or "unknown" (``raw_type`` set when the file gives a type
    number; the notes say what the object was). ``visible``: on one of the layers 1-8
    CoppeliaSim shows by default. ``detectable``: proximity sensors can see it (any of the
    object's ultrasonic, infrared, laser, inductive, capacitive flags; CoppeliaSim's models keep
    their respondable shapes undetectable and their visible shapes detectable). Exactly one of the
    ``*_data`` fields matches ``kind`` (None for kinds without data). ``name`` is the old-style
    unique name ("leftMotor#0" style); ``alias`` the 4.x alias ("" before 4.2)."""

    handle: int
    name: str
    kind: str
    parent: int | None = None
    pose: Pose = field(default_factory=Pose)
    alias: str = ""
    visible: bool = True
    model_base: bool = False
    detectable: bool = True
    raw_type: int | None = None
    shape: ShapeData | None = None
    joint: JointData | None = None
    proximity_sensor: ProximitySensorData | None = None
    vision_sensor: VisionSensorData | None = None
    force_sensor: ForceSensorData | None = None
    camera: CameraData | None = None
    light: LightData | None = None
    dummy: DummyData | None = None
    path: PathData | None = None
    not_dynamic: bool = False  # model override: no shape of its tree is dynamic
    not_respondable: bool = False  # model override: no shape of its tree responds


@dataclass(frozen=True)
class SceneNote:
    """Something a reader did not understand or could not read: kept, never silent."""

    where: str  # object name, or "file"
    message: str


@dataclass(frozen=True)
class CustomData:
    """A custom data block saved with the scene (``sim.readCustomDataBlock``): ``owner`` the
    object's name ("" for the scene's own), its tag, its bytes as hex (text, so that the scene
    cache's JSON holds it)."""

    owner: str
    tag: str
    hex: str


@dataclass(frozen=True)
class Scene:
    """A whole scene. ``objects`` in file order (parents before children is not guaranteed);
    ``version`` the format/program version the file declares; ``notes`` what was not understood.
    ``source`` is the file the scene came from (for messages only)."""

    objects: tuple[SceneObject, ...]
    scripts: tuple[Script, ...] = ()
    source: str = ""
    format: str = ""  # "ttt" or "xml"
    version: str = ""
    gravity: Vec3 = (0.0, 0.0, -9.81)
    notes: tuple[SceneNote, ...] = ()
    time_step: float = 0.05  # the simulation time step saved with the scene (s)
    custom_data: tuple[CustomData, ...] = ()  # custom data blocks (sims/scene/custom_data.py)
    script_parameters: tuple[CustomData, ...] = ()  # sim.getScriptSimulationParameter's
    physics: Physics = field(default_factory=Physics)
    ik_groups: tuple[IkGroup, ...] = ()
    textures: tuple[TextureImage, ...] = ()  # the texture objects (sims/scene/textures.py)

    def by_handle(self) -> Mapping[int, SceneObject]:
        """Objects by handle (read-only; built once per scene)."""
        return self._index[0]

    def children(self, handle: int | None) -> list[SceneObject]:
        """The objects whose parent is ``handle`` (None: the top level), in file order. From an
        index built once, so walking the whole tree is linear in the number of objects."""
        return list(self._index[1].get(handle, ()))

    @cached_property
    def _index(self) -> tuple[Mapping[int, SceneObject], dict[int | None, list[SceneObject]]]:
        table = {o.handle: o for o in self.objects}
        kids: dict[int | None, list[SceneObject]] = {}
        for o in self.objects:
            kids.setdefault(o.parent, []).append(o)
        return MappingProxyType(table), kids

    def path(self, obj: SceneObject) -> str:
        """The 4.x object path ``/a/b/c`` from aliases (names where no alias is saved); a
        parent loop (possible only in a broken file) ends the path where it repeats."""
        table = self.by_handle()
        parts: list[str] = []
        seen: set[int] = set()
        cur: SceneObject | None = obj
        while cur is not None and cur.handle not in seen:
            seen.add(cur.handle)
            parts.append(cur.alias or cur.name.split("#")[0])
            cur = table.get(cur.parent) if cur.parent is not None else None
        return "/" + "/".join(reversed(parts))
