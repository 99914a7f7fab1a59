"""What moves mechanisms in a ``.ttt`` file: the dynamics settings (``DYN``), the IK groups
(top-level ``IKO`` chunks, one per group) and the path objects (``PAT``) with their control
points.

Read off CoppeliaSim's library source (coppeliaSimLib: ``dynamicsContainer.cpp``,
``ikGroup_old.cpp``, ``ikElement_old.cpp``, ``path_old.cpp``, ``pathCont_old.cpp``,
``simplePathPoint_old.cpp``); chunk names starting ``_`` hold doubles, the others floats
(``Fields.real``). A separate module so that ttt.py only calls it.
"""

from __future__ import annotations

import math

from sims.scene.model_mech import IkElement, IkGroup, PathData, PathPoint, Physics
from sims.scene.ttt_chunks import Chunk, Fields, bit, chunk_list

ENGINES = {0: "bullet", 1: "ode", 2: "vortex", 3: "newton", 4: "mujoco", 5: "drake"}
IK_METHODS = {
    0: "pseudo_inverse",
    1: "damped_least_squares",
    2: "jacobian_transpose",
    3: "undamped",
}
PATH_CLOSED, PATH_AUTO_ORIENTATION = 4, 8  # sim_pathproperty_* bits


def read_physics(buf: bytes, chunk: Chunk) -> Physics:
    """The ``DYN`` chunk: engine, Bullet's step and constraint solving iterations, enabled."""
    engine, step, iterations, enabled = "bullet", 0.005, 100, True
    found_step = False
    for c in chunk_list(buf, chunk.start, chunk.end)[0]:
        f = Fields(buf, c)
        if c.name in ("Eng", "En2", "En3", "_n3"):
            engine = ENGINES.get(f.i32(), "bullet")
        elif c.name in ("Stp", "_tp"):
            step, found_step = f.real()[0], True
        elif c.name == "Bul":
            bullet_step, _scaling = f.f32(2)
            iterations = f.i32()
            if not found_step and engine == "bullet":
                step = bullet_step
        elif c.name in ("BuN", "_uN"):
            n_real, n_int = f.i32(), f.i32()
            reals = f.real(n_real) if n_real > 0 else ()
            ints = [f.i32() for _ in range(n_int)]
            if reals and not found_step and engine == "bullet":
                step = reals[0]
            if ints:
                iterations = ints[0]
        elif c.name == "Var":
            enabled = bit(f.u8(), 0)
    return Physics(engine, step if step > 0 else 0.005, max(1, iterations), enabled)


def read_ik_group(buf: bytes, chunk: Chunk) -> IkGroup:
    handle, name, iterations, damping, method = -1, "", 3, 0.1, 0
    flags = 1
    elements: list[IkElement] = []
    for c in chunk_list(buf, chunk.start, chunk.end)[0]:
        f = Fields(buf, c)
        if c.name == "Oid":
            handle = f.i32()
        elif c.name == "Nme":
            name = f.string()
        elif c.name == "Mit":
            iterations = f.i32()
        elif c.name in ("Dpg", "_pg"):
            damping = f.real()[0]
        elif c.name == "Cmt":
            method = f.i32()
        elif c.name == "Var":
            flags = f.u8()
        elif c.name == "Ike":
            elements.append(_ik_element(buf, c))
    return IkGroup(
        name=name or f"IK group {handle}",
        handle=handle,
        elements=tuple(elements),
        method=IK_METHODS.get(method, "pseudo_inverse"),
        damping=damping,
        iterations=max(1, iterations),
        enabled=bit(flags, 0),
        restore_if_position_not_reached=bit(flags, 1),
        restore_if_orientation_not_reached=bit(flags, 2),
        ignore_max_steps=not bit(flags, 5),
        explicit=bit(flags, 6),
    )


def _ik_element(buf: bytes, chunk: Chunk) -> IkElement:
    tip, base, reference, constraints = -1, -1, -1, 7
    linear, angular = 0.001, math.radians(0.5)
    weights = (1.0, 1.0)
    enabled = True
    for c in chunk_list(buf, chunk.start, chunk.end)[0]:
        f = Fields(buf, c)
        if c.name == "Ik2":
            tip, base = f.i32(), f.i32()
        elif c.name == "Abc":
            reference = f.i32()
        elif c.name == "Prc":  # angular in degrees, then linear
            angular, linear = f.f32(2)
            angular = math.radians(angular)
        elif c.name in ("Pr2", "_r2"):
            angular, linear = f.real(2)
        elif c.name == "Ctr":
            constraints = f.i32()
        elif c.name in ("Wgt", "_gt"):
            weights = tuple(f.real(2))  # type: ignore[assignment]
        elif c.name == "Var":
            enabled = bit(f.u8(), 0)
    return IkElement(
        tip=tip,
        base=base if base >= 0 else None,
        constraints=constraints,
        reference=reference if reference >= 0 else None,
        precision=(linear, angular),
        weights=weights,
        enabled=enabled,
    )


def read_path(buf: bytes, own: list[Chunk]) -> PathData:
    """A 3.x / 4.0-4.2 path object (its ``Ntp`` path container)."""
    for c in own:
        if c.name == "Ntp":
            return _container(buf, c)
    return PathData()


def _container(buf: bytes, chunk: Chunk) -> PathData:
    points: list[PathPoint] = []
    attributes = 0
    position = nominal = target = accel = 0.0
    method, angle_coeff = 0, 0.0
    for c in chunk_list(buf, chunk.start, chunk.end)[0]:
        f = Fields(buf, c)
        if c.name == "Pat":
            point = _point(buf, c)
            if point is not None:
                points.append(point)
        elif c.name == "At2":
            attributes = f.i32()
        elif c.name in ("Jm2", "_m2"):
            position, accel, nominal, target = f.real(4)
        elif c.name in ("Av3", "_v3"):
            angle_coeff = f.real()[0]
            method = f.i32()
    return PathData(
        points=tuple(points),
        closed=bool(attributes & PATH_CLOSED),
        position=position,
        nominal_velocity=nominal,
        target_velocity=target,
        max_acceleration=accel,
        length_method=method,
        angle_to_distance=angle_coeff,
        automatic_orientation=bool(attributes & PATH_AUTO_ORIENTATION),
    )


def _point(buf: bytes, chunk: Chunk) -> PathPoint | None:
    found = None
    on_spot = 0.0
    for c in chunk_list(buf, chunk.start, chunk.end)[0]:
        f = Fields(buf, c)
        if c.name in ("At2", "_t2"):
            tr = f.real(7)
            before, after = f.real(2)
            count = f.i32()
            velocity = f.real()[0]
            w, x, y, z = tr[3:7]
            norm = math.sqrt(w * w + x * x + y * y + z * z) or 1.0
            found = (
                (tr[0], tr[1], tr[2]),
                (x / norm, y / norm, z / norm, w / norm),
                (before, after),
                count,
                velocity,
            )
        elif c.name in ("At3", "_t3"):
            on_spot = f.real()[0]
    if found is None:
        return None
    pos, quat, bezier, count, velocity = found
    return PathPoint(pos, quat, bezier, count, velocity, on_spot)  # type: ignore[arg-type]
