"""The scene objects of a ``.ttt`` file other than shapes: the common part, joints, sensors,
cameras, lights, and the embedded scripts.

What the file holds (from CoppeliaSim's scene-object serializers; names are chunk names):
- common part (ends with ``NXT``): ``Ids`` (handle, parent handle or -1), ``Nme`` (old-style
  name), ``Ali`` (4.2+ alias), ``Cfq``/``_fq`` (local pose, quaternion w x y z then position),
  ``Va2``/``Va3`` (bit 0: model base), ``Lar`` (visibility layer bits; layers 1-8 show).
- joint: ``Jtt`` type (10 revolute, 11 prismatic, 12 spherical), ``Jmd`` mode (0 passive, 1
  "motion" (deprecated), 2 IK, 3/4 dependent, 5 force/torque), ``Va9`` bits (0 cyclic, 4 motor
  enabled, 5 position control enabled, 6 hybrid, 7 spring), ``Pmr`` minimum and range, ``Prt``
  position, ``Dmp`` target velocity and max force/torque, ``Dtp`` target position, ``Dp2`` PID
  (``Dpc``: older, I and D scaled by a 5 ms step), ``Spp`` spring K and C, ``Ulv`` upper
  velocity limit, ``Jdt`` dependency (master handle, multiplier, offset), ``Jsp`` screw pitch,
  ``Jst`` a spherical joint's rotation (w, x, y, z);
  4.4+ ``Dcm`` control mode (0 free, 1 force, 2 velocity, 3 position, 4 spring).
- proximity sensor: ``Snt`` type (30 pyramid, 31 cylinder, 32 disc, 33 cone, 34 ray), ``Vod``
  the volume (``Ss3``: offset, range, x/y size near and far, radius near and far, angle),
  ``Pr4`` bit 7 explicit handling, ``Pr5`` bit 1 randomized ray.
- vision sensor: ``Res`` resolution, ``Ccp`` ortho size, view angle, near, far; ``Va3`` bit 0
  perspective.
- dummy: ``Lli`` linked dummy handle (-1: none), ``Dl2`` link type (0 dynamics loop closure, 1
  dynamics force constraint, 2-4 GCS, 5 IK tip/target).
- camera: ``Cp3`` ortho size and view angle, ``Ccp`` near and far. Light: ``Cp2`` type (1 omni,
  2 spot, 3 directional), ``Cas`` bit 0 on, ``Cl2`` light colour. Force sensor: ``Fil`` filter
  samples, ``Vab`` threshold switches, ``Tre``/``Tri`` force and torque thresholds.
- script (top-level ``LST``): ``Si2`` (-, object handle, type: 0 main, 1 child, 6
  customization), ``Coc`` (V-REP 3.x: the object of a customization script), ``Va2`` bit 0
  threaded, bit 1 disabled, ``Ste`` the text, lightly scrambled
  (every byte but the first and last shifted by amounts derived from its index and those two);
  line ends are given as ``\n`` (as an XML reader gives them).
"""

from __future__ import annotations

import math

import numpy as np

from sims.scene.model import (
    CameraData,
    DummyData,
    ForceSensorData,
    JointData,
    LightData,
    Pose,
    ProximitySensorData,
    Script,
    VisionSensorData,
)
from sims.scene.ttt_chunks import Chunk, Fields, bit, chunk_list
from sims.scene.ttt_shapes import pose7, read_colors

JOINT_KINDS = {10: "revolute", 11: "prismatic", 12: "spherical"}
PROX_VOLUMES = {30: "pyramid", 31: "cylinder", 32: "disc", 33: "cone", 34: "ray"}
LIGHT_KINDS = {1: "omni", 2: "spot", 3: "directional"}
SCRIPT_KINDS = {0: "main", 1: "child", 6: "customization"}
LINK_TYPES = {
    0: "dynamics_loop_closure",
    1: "dynamics_force_constraint",
    2: "gcs_loop_closure",
    3: "gcs_tip",
    4: "gcs_target",
    5: "ik_tip_target",
}
DETECTABLE_BITS = 0x1F0  # ultrasonic, infrared, laser, inductive, capacitive
DYN_MODES = {0: "velocity", 1: "force", 2: "velocity", 3: "position", 4: "spring"}


class Common:
    """The common part of a scene object."""

    def __init__(self) -> None:
        self.handle: int | None = None
        self.parent: int | None = None
        self.name = ""
        self.alias = ""
        self.pose = Pose()
        self.model_base = False
        self.layer = 1
        self.detectable = True
        self.model_property = 0

    def read(self, buf: bytes, chunks: list[Chunk]) -> None:
        for c in chunks:
            f = Fields(buf, c)
            if c.name == "Ids":
                self.handle = f.i32()
                parent = f.i32()
                self.parent = parent if parent >= 0 else None
            elif c.name == "Nme":
                self.name = f.string()
            elif c.name == "Ali":
                self.alias = f.string()
            elif c.name in ("Cfq", "_fq"):
                self.pose = pose7(f.real(7))
            elif c.name in ("Var", "Va2", "Va3"):
                self.model_base = bit(f.u8(), 0)
            elif c.name == "Lar":
                self.layer = f.u16()
            elif c.name == "Omp":  # special properties: bits 4-8 detectable by a sensor type
                self.detectable = bool(f.i32() & DETECTABLE_BITS)
            elif c.name == "Mpo":  # model properties: 32 not dynamic, 64 not respondable
                self.model_property = f.i32() & 0x0FFF


def read_joint(buf: bytes, chunks: list[Chunk], notes: list[str]) -> JointData:
    v: dict[str, object] = {}
    flags = 0
    mode_code = 0
    dyn_mode: int | None = None
    for c in chunks:
        f = Fields(buf, c)
        n = c.name
        if n == "Jtt":
            code = f.i32()
            v["kind"] = JOINT_KINDS.get(code, "revolute")
            if code not in JOINT_KINDS:
                notes.append(f"joint type {code} not understood, read as revolute")
        elif n == "Jmd":
            mode_code = f.i32()
        elif n == "Va9":
            flags = f.u8()
        elif n in ("Pmr", "_mr"):
            v["minimum"], v["range"] = f.real(2)
        elif n in ("Prt", "_rt"):
            v["position"] = f.real()[0]
        elif n in ("Dmp", "_mp"):
            vel, force = f.real(2)
            v["target_velocity"], v["max_force"] = vel, abs(force)
        elif n == "Jm2":
            v["target_velocity"] = f.f32(3)[2]
        elif n in ("Dtp", "_tp"):
            v["target"] = f.real()[0]
        elif n == "Dpc":
            p, i, d = f.f32(3)
            v["p_gain"], v["i_gain"], v["d_gain"] = p, i / 0.005, d * 0.005
        elif n == "Dp2":
            v["p_gain"], v["i_gain"], v["d_gain"] = f.f32(3)
        elif n in ("Spp", "_pp"):
            v["spring_k"], v["spring_c"] = f.real(2)
        elif n == "Ulv":
            v["max_velocity"] = f.f32()[0]
        elif n in ("Ruc", "_uc"):
            v.setdefault("max_velocity", f.real()[0])
        elif n in ("Jdt", "_dt"):
            master = f.i32()
            v["dependent_on"] = master if master >= 0 else None
            v["coefficient"], v["offset"] = f.real(2)
        elif n in ("Jst", "_st"):
            w, x, y, z = f.real(4)
            norm = math.sqrt(w * w + x * x + y * y + z * z) or 1.0
            v["spherical_rotation"] = (x / norm, y / norm, z / norm, w / norm)
        elif n in ("Jsp", "_sp"):
            v["screw_pitch"] = f.real()[0]
        elif n in ("Ikw", "_kw"):
            v["ik_weight"] = f.real()[0]
        elif n == "Dcm":
            dyn_mode = f.i32()
    cyclic = bit(flags, 0)
    motor, ctrl, hybrid, spring = bit(flags, 4), bit(flags, 5), bit(flags, 6), bit(flags, 7)
    if mode_code == 5 or hybrid:
        if dyn_mode is not None:
            mode = DYN_MODES.get(dyn_mode, "position")
            if dyn_mode not in DYN_MODES:
                notes.append(f"joint control mode {dyn_mode} (callback) read as position control")
            motor = dyn_mode != 0
            ctrl = dyn_mode in (3, 4)
        elif not motor:
            mode = "velocity"  # with motor_enabled False: turns freely
        else:
            mode = "velocity" if not ctrl else ("spring" if spring else "position")
        if hybrid:
            notes.append("hybrid (IK + dynamics) joint: position control, IK sets its target")
            mode, motor, ctrl = "position", True, True
    elif mode_code in (3, 4):
        mode = "dependent"
    elif mode_code == 2:
        mode = "ik"
    else:
        mode = "passive"
        if mode_code == 1:
            notes.append("deprecated 'motion' joint mode read as passive")
        elif mode_code != 0:
            notes.append(f"joint mode {mode_code} not understood, read as passive")
    if mode == "force":
        notes.append("force-control joint mode read as velocity control at its target")
        mode = "velocity"
    return JointData(
        cyclic=cyclic and v.get("kind", "revolute") == "revolute",
        mode=mode,
        motor_enabled=motor,
        control_enabled=ctrl,
        hybrid=hybrid,
        **v,  # type: ignore[arg-type]
    )


def read_dummy(buf: bytes, chunks: list[Chunk]) -> DummyData:
    linked: int | None = None
    link_type = 0
    flags, offset = 0, 0.0
    for c in chunks:
        f = Fields(buf, c)
        if c.name == "Lli":
            handle = f.i32()
            linked = handle if handle >= 0 else None
        elif c.name == "Dl2":
            link_type = f.i32()
        elif c.name == "Var":  # bits: 1 follows its parent path, 2 free on it
            flags = f.u8()
        elif c.name in ("Po4", "Po5", "_o5"):  # offset along the parent path
            offset = f.real()[0]
    return DummyData(
        linked_to=linked,
        link_type=LINK_TYPES.get(link_type, str(link_type)),
        follows_path=bit(flags, 1),
        path_offset=offset,
        free_on_path=bit(flags, 2),
    )


def read_proximity(buf: bytes, chunks: list[Chunk]) -> ProximitySensorData:
    volume = "ray"
    randomized = explicit = False
    vol: tuple[float, ...] = (0.0, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    for c in chunks:
        f = Fields(buf, c)
        if c.name == "Snt":
            volume = PROX_VOLUMES.get(f.i32(), "ray")
        elif c.name == "Pr5":
            randomized = bit(f.u8(), 1)
        elif c.name == "Pr4":
            explicit = bit(f.u8(), 7)
        elif c.name == "Vod":
            for vc in chunk_list(buf, c.start, c.end)[0]:
                if vc.name in ("Ss3", "_s3"):
                    vol = Fields(buf, vc).real(9)
    offset, rng, xs, ys, xfar, yfar, radius, radius_far, angle = vol
    if volume == "ray" and randomized:
        volume = "randomized_ray"
    size = (xfar, yfar) if volume == "pyramid" else (2 * radius, 2 * radius_far)
    return ProximitySensorData(
        volume=volume, range=rng, offset=offset, angle=angle, size=size, explicit=explicit
    )


def read_vision(buf: bytes, chunks: list[Chunk]) -> VisionSensorData:
    v: dict[str, object] = {}
    for c in chunks:
        f = Fields(buf, c)
        if c.name == "Res":
            v["resolution"] = (f.i32(), f.i32())
        elif c.name in ("Ccp", "_cp"):
            v["ortho_size"], v["view_angle"], v["near"], v["far"] = f.real(4)
        elif c.name == "Va3":
            v["perspective"] = bit(f.u8(), 0)
    return VisionSensorData(**v)  # type: ignore[arg-type]


def read_camera(buf: bytes, chunks: list[Chunk]) -> CameraData:
    v: dict[str, object] = {}
    for c in chunks:
        f = Fields(buf, c)
        if c.name in ("Cp3", "_p3"):
            _ortho, v["view_angle"] = f.real(2)
        elif c.name in ("Ccp", "_cp"):
            v["near"], v["far"] = f.real(2)
    return CameraData(**v)  # type: ignore[arg-type]


def read_light(buf: bytes, chunks: list[Chunk]) -> LightData:
    v: dict[str, object] = {}
    for c in chunks:
        f = Fields(buf, c)
        if c.name == "Cp2":
            v["kind"] = LIGHT_KINDS.get(f.i32(), "omni")
        elif c.name == "Cas":
            v["enabled"] = bit(f.u8(), 0)
        elif c.name == "Cl2":
            colors = read_colors(buf, c)
            if colors:
                v["diffuse"] = tuple(min(1.0, max(0.0, x)) for x in colors[3:6])
    return LightData(**v)  # type: ignore[arg-type]


def read_force_sensor(buf: bytes, chunks: list[Chunk]) -> ForceSensorData:
    samples = 1
    enabled = (False, False)
    force = torque = None
    for c in chunks:
        f = Fields(buf, c)
        if c.name == "Fil":
            samples = f.i32()
        elif c.name == "Vab":
            flags = f.u8()
            enabled = (bit(flags, 0), bit(flags, 1))
        elif c.name in ("Tre", "Tri", "_ri"):
            force, torque = f.real(2)
    return ForceSensorData(
        filter_samples=samples,
        force_threshold=force if enabled[0] else None,
        torque_threshold=torque if enabled[1] else None,
    )


def unscramble(raw: bytes) -> bytes:
    """Undo the light scrambling of a stored script text (see the module docstring)."""
    n = len(raw)
    if n < 3:
        return raw
    data = np.frombuffer(raw, dtype=np.int8).astype(np.int64)
    start = int(data[0] / 2)  # C integer division truncates toward zero
    end = int(data[-1]) * 3
    i = np.arange(1, n - 1, dtype=np.int64)
    mid = data[1:-1].copy()
    mid += np.where(i & 1, i + start + end, 0)
    mid -= np.where(i & 2, 3 * i + start, 0)
    mid += np.where(i & 4, i // 2 + end, 0)
    out = bytearray(raw)
    out[1:-1] = (mid & 0xFF).astype(np.uint8).tobytes()
    return bytes(out)


def read_script(buf: bytes, chunks: list[Chunk], notes: list[str]) -> Script | None:
    obj: int | None = None
    kind_code = 1
    threaded = disabled = False
    text = ""
    for c in chunks:
        f = Fields(buf, c)
        if c.name == "Si2":
            f.i32()
            handle = f.i32()
            obj = handle if handle >= 0 else None
            kind_code = f.i32()
        elif c.name == "Va2":
            flags = f.u8()
            threaded, disabled = bit(flags, 0), bit(flags, 1)
        elif c.name == "Coc":  # V-REP 3.x: the object a customization script is attached to
            handle = f.i32()
            if handle >= 0:
                obj = handle
        elif c.name == "Ste":
            raw = unscramble(f.rest()).rstrip(b"\0").replace(b"\r\n", b"\n")
            text = raw.decode("utf-8", errors="replace")
    kind = SCRIPT_KINDS.get(kind_code & 0x0F)
    if kind_code & 0xF0:
        threaded = True
    if kind is None:
        notes.append(f"script of type {kind_code} (an old callback script) skipped")
        return None
    return Script(
        kind=kind,
        text=text,
        object=obj if kind != "main" else None,
        threaded=threaded,
        disabled=disabled,
    )
