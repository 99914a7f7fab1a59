"""Scene model records for mechanisms: the physics engine settings, IK groups and path objects.

Part of the scene model (``sims/scene/model.py`` re-exports them; the same conventions hold:
SI units, radians, quaternions (x, y, z, w), poses local to the parent). Apart from model.py so
that what moves mechanisms is read in one place; this module imports nothing of ours.
"""

from __future__ import annotations

from dataclasses import dataclass

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]


@dataclass(frozen=True)
class Physics:
    """The scene's dynamics settings: ``engine`` ("bullet", "ode", "vortex", "newton",
    "mujoco"), the dynamics ``step`` (s), the engine's constraint solver ``iterations`` and
    whether dynamics is ``enabled`` at all. Defaults are CoppeliaSim's (Bullet, 5 ms, 100)."""

    engine: str = "bullet"
    step: float = 0.005
    iterations: int = 100
    enabled: bool = True


#: IK constraint bits (CoppeliaSim's sim_ik_x_constraint ...).
IK_X, IK_Y, IK_Z, IK_ALPHA_BETA, IK_GAMMA = 1, 2, 4, 8, 16


@dataclass(frozen=True)
class IkElement:
    """One tip of an IK group: ``tip`` (a dummy; its linked dummy is the target) solved over
    the joints between ``base`` (None: the world) and the tip. ``constraints``: the IK_* bits
    of what is matched; ``reference``: the frame they are expressed in (None: the base).
    ``precision``: linear (m) and angular (rad) tolerances; ``weights``: of the position and
    orientation rows."""

    tip: int
    base: int | None = None
    constraints: int = IK_X | IK_Y | IK_Z
    reference: int | None = None
    precision: tuple[float, float] = (0.001, 0.0087266)
    weights: tuple[float, float] = (1.0, 1.0)
    enabled: bool = True
    target: int | None = None  # None: the tip's linked dummy (saved groups); simIK names it
    all_joints: bool = False  # every joint of the chain takes part (simIK), not only IK-mode ones


@dataclass(frozen=True)
class IkGroup:
    """An IK group saved with the scene. ``method``: "pseudo_inverse", "damped_least_squares",
    "jacobian_transpose" or "undamped" (CoppeliaSim's calculation methods); ``damping`` its
    damping factor; ``iterations`` the most it takes per resolution. ``explicit``: only solved
    when a script asks (sim.handleIkGroup), not by the main script's pass."""

    name: str
    handle: int
    elements: tuple[IkElement, ...] = ()
    method: str = "pseudo_inverse"
    damping: float = 0.1
    iterations: int = 3
    enabled: bool = True
    explicit: bool = False
    ignore_max_steps: bool = True
    restore_if_position_not_reached: bool = False
    restore_if_orientation_not_reached: bool = False


@dataclass(frozen=True)
class PathPoint:
    """A control point of a path (in the path's frame) with its Bézier corner: the factors
    before and after (0..1: how much of each neighbouring segment is rounded) and the number of
    points of the rounded corner (1: a sharp corner)."""

    position: Vec3
    quaternion: Quat = (0.0, 0.0, 0.0, 1.0)
    bezier: tuple[float, float] = (0.5, 0.5)
    bezier_points: int = 15
    max_velocity: float = 1.0  # relative to the path's nominal velocity
    on_spot_distance: float = 0.0


@dataclass(frozen=True)
class PathData:
    """A path object: control points, ``closed``, the 3.x path's current ``position`` along it
    (m, from the start) and its nominal velocity (m/s: CoppeliaSim moves the position by it
    each pass, dragging the dummies that follow the path). ``length_method``: how a segment's
    length is measured (0: its distance; CoppeliaSim's sim_distcalcmethod_*)."""

    points: tuple[PathPoint, ...] = ()
    closed: bool = False
    position: float = 0.0
    nominal_velocity: float = 0.0
    target_velocity: float = 0.0
    max_acceleration: float = 0.0
    length_method: int = 0
    angle_to_distance: float = 0.0
    automatic_orientation: bool = False
