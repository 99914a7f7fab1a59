"""Reader for CoppeliaSim's binary scene format (``.ttt``, V-REP 3.x and CoppeliaSim 4.x).

What the file holds (from CoppeliaSim's serializer, ``ser.cpp``): a 1021-byte header: ``VREP``,
int32 serialization version (18 for V-REP 3.3-3.5, 20-22 for CoppeliaSim 4.0-4.1, 25 for 4.10),
int32 oldest serialization version able to read the file, one byte compression method (0 none,
1 Huffman), int32 uncompressed size, int32 build flavour, uint16 program version (e.g. 40100 for
4.1.0), uint32 licence, one byte revision, one byte file type, 992 reserved bytes. The body
follows, compressed as described in :mod:`sims.scene.ttt_huffman`; decompressed, it is the chunk
sequence described in :mod:`sims.scene.ttt_chunks`: shared mesh arrays, materials, textures, the
scene objects (``SHP`` shape, ``JNT`` joint, ``DMY`` dummy, ``SNR`` proximity sensor, ``RSN``
vision sensor, ``FSE`` force sensor, ``CMA`` camera, ``LGT`` light, ``SCT`` 4.6+ script object
whose ``Soo`` part is a script, ...), scripts (``LST``) and
scene settings (``DYN`` gravity, ``SIM`` time step).

Reading is bounded (:mod:`sims.scene.limits`): the header's uncompressed size may be at most
``MAX_RATIO`` times the compressed body and at most ``MAX_BODY`` bytes; the body is decoded in
windows and its chunks read one at a time, so memory follows the file, not what its header
claims; meshes, objects and compound nesting have bounds of their own.

Reading is pure data: nothing in the file is executed. Whatever is skipped (object types we do
not model, chunks we do not know, settings of no use to a pybullet world) is listed in
``Scene.notes``; a file that cannot be read raises :class:`SceneError` naming the object.
"""

from __future__ import annotations

import struct
from dataclasses import replace

from sims.scene import custom_data
from sims.scene.errors import SceneError
from sims.scene.limits import (
    MAX_BODY,
    MAX_RATIO,
    LimitError,
    TextureBudget,
    check_depth,
    check_object_count,
)
from sims.scene.model import (
    IkGroup,
    Physics,
    Scene,
    SceneNote,
    SceneObject,
    Script,
    TextureImage,
)
from sims.scene.textures import attach_images, read_texture_object
from sims.scene.ttt_chunks import Chunk, ChunkError, Fields, chunk_list, top_level
from sims.scene.ttt_huffman import HuffmanError, decompress
from sims.scene.ttt_mech import read_ik_group, read_path, read_physics
from sims.scene.ttt_objects import (
    Common,
    read_camera,
    read_dummy,
    read_force_sensor,
    read_joint,
    read_light,
    read_proximity,
    read_script,
    read_vision,
)
from sims.scene.ttt_shapes import (
    Pool,
    ShapeReader,
    material_id,
    read_friction,
    read_pool,
    shape_flags,
)

HEADER_SIZE = 1021
OLDEST_VERSION = 18  # the oldest serialization CoppeliaSim itself still reads
NEWEST_VERSION = 25  # the newest serialization whose description we read

OBJECT_KINDS = {
    "SHP": "shape",
    "JNT": "joint",
    "DMY": "dummy",
    "SNR": "proximity_sensor",
    "RSN": "vision_sensor",
    "FSE": "force_sensor",
    "CMA": "camera",
    "LGT": "light",
    "GRH": "graph",
    "PAT": "path",
    "OCT": "octree",
    "PTC": "point_cloud",
    "MIR": "mirror",
    "MIL": "mill",
    "MKR": "marker",
    "SCT": "script",
    "CSO": "custom",
}
# Top-level chunks that hold nothing a pybullet world needs: read past, said once in the notes.
SETTINGS = {
    "MTC": "thumbnail",
    "BBC": "model thumbnail info",
    "GHO": "ghosts",
    "ENV": "environment (background, fog)",
    "SET": "main settings",
    "VEW": "views",
    "ORD": "object order",
    "COB": "custom objects",
    "BBK": "old custom user interfaces",
    "COL": "collision objects",
    "DST": "distance objects",
    "GRP": "collections",
    "PPL": "path planning tasks",
}


# Chunk names each object type's serializer knows (from the library's loading code, plus the
# colour chunks V-REP 3.x wrote and newer versions skip). Others are listed in the notes.
_COLORS = {"Cl0", "Cl1", "Cl2", "Cl3", "Cl4"}
KNOWN_CHUNKS = {
    "common": set(
        "3do Ack Ali Alt Am2 Amv Anm Avo Cda Cfq Cod Cor Cr2 Crh Hci Ids Lar Lsp Mpo Nme Om5 Omi "
        "Omp Omr Oot Op2 Or2 Orh Ots Rst Sci Scp Sep Sfa Sfb Tdo Uis Ups Va2 Va3 Va4 Var _do _fa "
        "_fb _fq _lt _m5 _mr".split()
    ),
    "joint": set(
        "Arg Bt1 BtN Cco Dcm Dmp Dp2 Dpc Dpm Dtp Dvm Ikw Jdt Jm2 Jm3 Jmd Jsp Jst Jtt Mj3 Mss Nw1 "
        "Od1 OdN Pmr Prt Ruc Sld Spp Ulv V10 Va9 Vaa Vo2 _dN _dt _j3 _kw _m3 _mp _mr _o2 _pp _rg "
        "_rt _sp _ss _st _tN _tp _uc _w1".split()
    ),
    "dummy": set("Ack Atg Dl2 Dy2 Lli Mj1 Po4 Po5 Var _j1 _o5 _y2".split()),
    "proximity_sensor": set("Al2 Pr4 Pr5 Rad Sns Snt Sox Sst Vod _l2 _ns al3".split()),
    "vision_sensor": set("Afr Ccp Cfr Db2 Dox Pv1 Res Rmd Si2 Siz Va2 Va3 Var _cp _i2".split()),
    "force_sensor": set("Fil Siz Tre Tri Vab _iz _ri".split()),
    "camera": set("Ca2 Ca3 Caz Ccp Cmp Cp3 Cp4 Cpm Pv1 Rm2 Rmd _cp _p3 _p4".split()),
    "light": set("Caf Cas Cp2 Cp3 Pfd _af _p2 _p3".split()),
    "unknown": set("Sos Var Soc Soo".split()),  # script objects (4.6+)
    "shape": set("Dc2 Ge2 Idv Mat Ss2 Ss3 Sss _dv".split()),
}


def read_header(data: bytes, source: str) -> tuple[int, int, int, str]:
    """(serialization version, compression, uncompressed size, program version text)."""
    if len(data) < HEADER_SIZE or data[:4] != b"VREP":
        raise SceneError(source, "header", "not a CoppeliaSim scene (no complete VREP header)")
    version, oldest_reader = struct.unpack_from("<ii", data, 4)
    compression = data[12]
    (size,) = struct.unpack_from("<i", data, 13)
    (program,) = struct.unpack_from("<H", data, 21)
    text = f"{program // 10000}.{program // 100 % 100}.{program % 100}" if program else "?"
    if version < OLDEST_VERSION:
        raise SceneError(
            source,
            "header",
            f"serialization version {version} is older than any CoppeliaSim still reads "
            f"(oldest {OLDEST_VERSION}); re-save the scene with a newer CoppeliaSim",
        )
    if oldest_reader > NEWEST_VERSION:
        raise SceneError(
            source,
            "header",
            f"serialization version {version} (CoppeliaSim {text}) needs a reader for version "
            f"{oldest_reader} or newer; this reader knows up to {NEWEST_VERSION}",
        )
    if compression not in (0, 1):
        raise SceneError(source, "header", f"unknown compression method {compression}")
    if size < 0:
        raise SceneError(source, "header", f"implausible uncompressed size {size}")
    body_bytes = len(data) - HEADER_SIZE
    if compression == 1 and size > MAX_RATIO * body_bytes + 4096:
        raise SceneError(
            source,
            "header",
            f"claims {size} bytes of scene data from {body_bytes} compressed bytes, "
            f"{size / max(body_bytes, 1):.0f} times as many: real scenes compress less than "
            f"{MAX_RATIO} times; the file is corrupt or made to exhaust memory",
        )
    if size > MAX_BODY:
        raise SceneError(
            source,
            "header",
            f"claims {size} bytes of scene data, more than the {MAX_BODY} this reader accepts "
            f"(course scenes hold under 2 MB)",
        )
    return version, compression, size, text


def body(data: bytes, source: str) -> tuple[bytes, int, str]:
    """The decompressed chunk data, the serialization version and the program version."""
    version, compression, size, program = read_header(data, source)
    raw = memoryview(data)[HEADER_SIZE:]  # no copy of the body
    if compression == 0:
        if len(raw) < size:
            raise SceneError(source, "file", f"truncated: {len(raw)} of {size} bytes")
        return bytes(raw[:size]), version, program
    try:
        return decompress(raw, size), version, program
    except HuffmanError as exc:
        raise SceneError(source, "file", f"corrupt or truncated compressed data: {exc}") from None


def read_ttt(data: bytes, source: str) -> Scene:
    buf, version, program = body(data, source)
    chunks = top_level(buf)  # one at a time: a body of millions of empty chunks costs nothing
    notes: list[SceneNote] = []
    pool = Pool()
    materials: dict[int, float | None] = {}
    objects: list[SceneObject] = []
    scripts: list[Script] = []
    gravity = (0.0, 0.0, -9.81)
    time_step = 0.05
    physics = Physics()
    ik_groups: list[IkGroup] = []
    skipped: dict[str, int] = {}
    custom: list = []
    params: list = []
    unknown_chunks: dict[tuple[str, str], list[str]] = {}
    unknown_top: dict[str, int] = {}
    textures: dict[int, TextureImage] = {}
    texture_budget = TextureBudget()
    while True:
        try:
            c = next(chunks, None)
        except ChunkError as exc:
            raise SceneError(source, "file", f"corrupt scene data: {exc}") from None
        if c is None:
            break
        try:
            if c.name == "VIN":
                pool = read_pool(buf, c, pool.budget)
            elif c.name == "DMA":
                mid = material_id(buf, c)
                if mid is not None:
                    materials[mid] = read_friction(buf, c)
            elif c.name in OBJECT_KINDS:
                check_object_count(len(objects) + 1)
                obj = _read_object(buf, c, pool, materials, notes, len(objects), source, scripts)
                if obj is not None:
                    _unknown(buf, c, obj, unknown_chunks)
                if obj is not None:
                    objects.append(obj)
                    custom += custom_data.object_blocks(buf, c, obj.name)
                    params += custom_data.script_parameters(buf, c, obj.name)
            elif c.name in ("CDA", "CDS"):  # the scene's own custom data
                custom += custom_data.blocks(buf, c, "")
            elif c.name == "LST":
                local: list[str] = []
                script = read_script(buf, chunk_list(buf, c.start, c.end)[0], local)
                notes.extend(SceneNote("script", m) for m in local)
                if script is not None:
                    scripts.append(script)
            elif c.name == "DYN":
                gravity = _gravity(buf, c) or gravity
                physics = read_physics(buf, c)
            elif c.name == "TEX":
                image = read_texture_object(buf, c, texture_budget)
                textures[image.id] = image
            elif c.name == "IKO":
                ik_groups.append(read_ik_group(buf, c))
            elif c.name == "SIM":
                time_step = _time_step(buf, c) or time_step
            elif c.name in SETTINGS:
                skipped[SETTINGS[c.name]] = skipped.get(SETTINGS[c.name], 0) + 1
            else:
                unknown_top[c.name] = unknown_top.get(c.name, 0) + 1
        except LimitError as exc:
            raise SceneError(source, "file", str(exc)) from None
        except (ChunkError, struct.error, ValueError) as exc:
            where = f"{OBJECT_KINDS[c.name]} #{len(objects)}" if c.name in OBJECT_KINDS else "file"
            where = f"texture #{len(textures)}" if c.name == "TEX" else where
            raise SceneError(source, where, f"corrupt {c.name!r} chunk: {exc}") from None
    for name, count in unknown_top.items():
        times = f" ({count} times)" if count > 1 else ""
        notes.append(SceneNote("file", f"unknown top-level chunk {name!r} skipped{times}"))
    for (kind, name), owners in sorted(unknown_chunks.items()):
        shown = ", ".join(owners[:3]) + (f" and {len(owners) - 3} more" if len(owners) > 3 else "")
        notes.append(
            SceneNote("file", f"{kind} chunk {name!r} not understood, skipped (in {shown})")
        )
    if skipped:
        listed = ", ".join(sorted(skipped))
        notes.append(SceneNote("file", f"not used by the simulation, skipped: {listed}"))
    for name in attach_images(objects, textures):
        notes.append(SceneNote(name, "its texture is not in the file: drawn without it"))
    try:
        objects = _check_tree(objects, scripts, notes)
    except LimitError as exc:
        raise SceneError(source, "file", str(exc)) from None
    return Scene(
        objects=tuple(objects),
        scripts=tuple(scripts),
        source=source,
        format="ttt",
        version=f"serialization {version}, CoppeliaSim {program}",
        gravity=gravity,
        notes=tuple(notes),
        time_step=time_step,
        custom_data=tuple(custom),
        script_parameters=tuple(params),
        physics=physics,
        ik_groups=tuple(ik_groups),
        textures=tuple(textures.values()),
    )


def _read_object(
    buf: bytes,
    chunk: Chunk,
    pool: Pool,
    materials: dict[int, float | None],
    notes: list[SceneNote],
    index: int,
    source: str,
    scripts: list[Script],
) -> SceneObject | None:
    kind = OBJECT_KINDS[chunk.name]
    base, pos = chunk_list(buf, chunk.start, chunk.end)
    own, _ = chunk_list(buf, pos, chunk.end)
    common = Common()
    common.read(buf, base)
    name = common.name or f"{kind} #{index}"
    if common.handle is None:
        notes.append(SceneNote(name, "object without a handle skipped"))
        return None
    local: list[str] = []
    extra: dict[str, object] = {}
    raw_type = None
    try:
        if kind == "shape":
            extra["shape"] = _read_shape(buf, own, pool, materials, local)
        elif kind == "joint":
            extra["joint"] = read_joint(buf, own, local)
        elif kind == "proximity_sensor":
            extra["proximity_sensor"] = read_proximity(buf, own)
        elif kind == "vision_sensor":
            extra["vision_sensor"] = read_vision(buf, own)
        elif kind == "force_sensor":
            extra["force_sensor"] = read_force_sensor(buf, own)
        elif kind == "camera":
            extra["camera"] = read_camera(buf, own)
        elif kind == "light":
            extra["light"] = read_light(buf, own)
        elif kind == "dummy":
            extra["dummy"] = read_dummy(buf, own)
        elif kind == "path":
            extra["path"] = read_path(buf, own)
        elif kind == "script":  # CoppeliaSim 4.6+: a script is an object of the tree
            for c in own:
                if c.name == "Soo":
                    script = read_script(buf, chunk_list(buf, c.start, c.end)[0], local)
                    if script is not None:
                        attached = common.parent if script.kind != "main" else None
                        scripts.append(replace(script, object=attached))
            local.append("script object kept in the tree as a frame; its text is with the scripts")
            kind = "unknown"
        else:
            local.append(f"{kind} objects are not simulated: kept in the tree without their data")
            if kind in ("marker", "custom"):
                kind, raw_type = "unknown", None
    except LimitError as exc:
        raise SceneError(source, name, str(exc)) from None
    except (ChunkError, struct.error) as exc:
        raise SceneError(source, name, f"corrupt {chunk.name!r} object: {exc}") from None
    notes.extend(SceneNote(name, m) for m in local)
    return SceneObject(
        handle=common.handle,
        name=name,
        kind=kind,
        parent=common.parent,
        pose=common.pose,
        alias=common.alias,
        visible=bool(common.layer & 0xFF),
        model_base=common.model_base,
        detectable=common.detectable,
        not_dynamic=bool(common.model_property & 32),
        not_respondable=bool(common.model_property & 64),
        raw_type=raw_type,
        **extra,  # type: ignore[arg-type]
    )


def _unknown(buf: bytes, chunk: Chunk, obj: SceneObject, found: dict) -> None:
    """Record the chunks of an object that its type's serializer does not know."""
    known = KNOWN_CHUNKS.get(obj.kind)
    if known is None:
        return
    base, pos = chunk_list(buf, chunk.start, chunk.end)
    own, _ = chunk_list(buf, pos, chunk.end)
    for c in base:
        if c.name not in KNOWN_CHUNKS["common"]:
            found.setdefault(("object", c.name), []).append(obj.name)
    for c in own:
        if c.name not in known and c.name not in _COLORS:
            found.setdefault((obj.kind, c.name), []).append(obj.name)


def _read_shape(
    buf: bytes,
    own: list[Chunk],
    pool: Pool,
    materials: dict[int, float | None],
    local: list[str],
):
    unknown: set[str] = set()
    reader = ShapeReader(buf, pool, unknown)
    friction = None
    for c in own:
        if c.name == "Ge2":
            reader.read_geometry(c)
        elif c.name == "Mat":
            friction = read_friction(buf, c)
    if friction is None and reader.root.material is not None:
        friction = materials.get(reader.root.material)
    static, respondable, mask = shape_flags(buf, own)
    local.extend(f"{u} not understood, skipped" for u in sorted(unknown))
    return reader.shape(reader.dynamics(static, respondable, mask, friction))


def _gravity(buf: bytes, chunk: Chunk) -> tuple[float, float, float] | None:
    for c in chunk_list(buf, chunk.start, chunk.end)[0]:
        if c.name in ("En2", "En3", "_n3"):
            f = Fields(buf, c)
            f.i32()
            g = f.real(3)
            return (g[0], g[1], g[2])
    return None


def _time_step(buf: bytes, chunk: Chunk) -> float | None:
    for c in chunk_list(buf, chunk.start, chunk.end)[0]:
        if c.name in ("Sts", "_ts"):
            return Fields(buf, c).real()[0]
    return None


def _check_tree(
    objects: list[SceneObject], scripts: list[Script], notes: list[SceneNote]
) -> list[SceneObject]:
    """Objects whose parent is missing, or which sit on a parent loop, become top-level (said
    in the notes); objects nested deeper than the limit are an error (LimitError)."""
    handles = {o.handle for o in objects}
    out = []
    for o in objects:
        if o.parent is not None and o.parent not in handles:
            notes.append(SceneNote(o.name, f"parent handle {o.parent} is not in the file"))
            o = replace(o, parent=None)
        out.append(o)
    loops = check_depth(out)
    for i, o in enumerate(out):
        if o.handle in loops:
            notes.append(SceneNote(o.name, "in a parent loop: put at the top"))
            out[i] = replace(o, parent=None)
    for s in scripts:
        if s.object is not None and s.object not in handles:
            notes.append(SceneNote("script", f"attached to handle {s.object}, not in the file"))
    return out
