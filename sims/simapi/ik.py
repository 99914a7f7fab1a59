"""``simIK.*``: CoppeliaSim 4.x's kinematics plug-in, on IK groups a script builds from the
scene's objects (``simIK.addIkElementFromScene`` / 4.6's ``addElementFromScene``).

An environment here is an ``IkEnvironment`` over the World (sims/ik_environment.py: the same
solver as the IK groups saved with scenes) plus the environment's own joint values and joint
modes. Its objects keep their scene handles: the map ``addIkElementFromScene`` returns sends each
scene object of the chain to itself, which is all scripts do with it (look a joint up, pass it
back to ``simIK.*``). ``handleIkGroup`` solves inside the environment only (the scene is not
touched; ``simIK.getJointPosition`` reads the result); ``applyIkEnvironmentToScene`` and
``handleGroup`` with ``syncWorlds`` copy the scene's joint values in, solve, and write the result
back as the plug-in does (a dynamically driven joint gets it as its motor's target, another one
is put there). Deviation, said here: targets and bases are read from the scene at each
resolution, i.e. as if synced, where the plug-in keeps its own copy until the next sync.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Any

from sims.ik_environment import IkEnvironment
from sims.kinematics import FAIL, NOT_PERFORMED, SUCCESS

from .context import Caller, SimError, store
from .values import integer, number, numbers, options, table, text

METHODS = {0: "pseudo_inverse", 1: "damped_least_squares", 2: "jacobian_transpose", 3: "undamped"}
PASSIVE, IK, DEPENDENT = 0, 2, 4  # simIK.jointmode_*

#: simIK's constants (CoppeliaSim 4.x's simIK.lua / plug-in values)
CONSTANTS: dict[str, int] = {
    "method_pseudo_inverse": 0,
    "method_damped_least_squares": 1,
    "method_jacobian_transpose": 2,
    "method_undamped_pseudo_inverse": 3,
    "constraint_x": 1,
    "constraint_y": 2,
    "constraint_z": 4,
    "constraint_alpha_beta": 8,
    "constraint_gamma": 16,
    "constraint_position": 7,
    "constraint_orientation": 24,
    "constraint_pose": 31,
    "result_not_performed": NOT_PERFORMED,
    "result_success": SUCCESS,
    "result_fail": FAIL,
    "jointmode_passive": PASSIVE,
    "jointmode_ik": IK,
    "jointmode_dependent": DEPENDENT,
    "jointtype_revolute": 10,
    "jointtype_prismatic": 11,
    "jointtype_spherical": 12,
    "handle_world": -1,
    "handle_parent": -11,
    "calc_notperformed": 1,
    "calc_cannotinvert": 2,
    "calc_notwithintolerance": 4,
    "calc_stepstoobig": 8,
    "calc_limithit": 16,
    "calc_invalidcallbackdata": 32,
}


@dataclass
class Env:
    """One simIK environment: its groups and its own joint values and modes (by joint name)."""

    kin: IkEnvironment
    joints: dict[str, float] = field(default_factory=dict)
    modes: dict[str, int] = field(default_factory=dict)


def _envs(c: Caller) -> dict[int, Env]:
    return store(c.world).ik_envs


def _env(c: Caller, env: Any) -> Env:
    found = _envs(c).get(integer(env, 1))
    if found is None:
        raise SimError(f"argument 1: no IK environment with handle {env}")
    return found


def _group(e: Env, group: Any) -> int:
    g = integer(group, 2)
    if g not in e.kin.groups:
        raise SimError(f"argument 2: no IK group with handle {g} in this environment")
    return g


def _joint_name(c: Caller, e: Env, joint: Any, position: int = 2) -> str:
    h = c.handle(joint, position)
    if not c.world.is_joint(h):
        raise SimError(f"argument {position}: object {h} is not a joint")
    return c.world.object_name(h)


# -- environments and groups ---------------------------------------------------------------------
def create_environment(c: Caller, flags: Any = 0) -> int:
    envs = _envs(c)
    handle = max(envs, default=0) + 1
    envs[handle] = Env(IkEnvironment(c.world))
    return handle


def erase_environment(c: Caller, env: Any) -> None:
    _env(c, env)
    del _envs(c)[integer(env, 1)]


def duplicate_environment(c: Caller, env: Any) -> int:
    e = _env(c, env)
    envs = _envs(c)
    handle = max(envs, default=0) + 1
    kin = IkEnvironment(c.world, copy.deepcopy(e.kin.groups))
    envs[handle] = Env(kin, dict(e.joints), dict(e.modes))
    return handle


def create_group(c: Caller, env: Any, name: Any = "") -> int:
    return _env(c, env).kin.create_group(text(name, 2) if name is not None else "")


def get_group_handle(c: Caller, env: Any, name: Any) -> int:
    try:
        return _env(c, env).kin.group_handle(text(name, 2))
    except KeyError as exc:
        raise SimError(str(exc).strip("'\"")) from None


def set_group_calculation(
    c: Caller, env: Any, group: Any, method: Any, damping: Any = 0.1, iterations: Any = 3
) -> None:
    e = _env(c, env)
    m = integer(method, 3)
    if m not in METHODS:
        raise SimError(f"argument 3: unknown calculation method {m}")
    e.kin.set_group_calculation(
        _group(e, group), METHODS[m], number(damping, 4), integer(iterations, 5)
    )


# -- elements ------------------------------------------------------------------------------------
def add_element_from_scene(
    c: Caller, env: Any, group: Any, base: Any, tip: Any, target: Any, constraints: Any = 31
) -> tuple[int, dict[int, int]]:
    """The element (its handle) and the scene-to-environment map of the objects it uses."""
    e = _env(c, env)
    g = _group(e, group)
    w = c.world
    b = integer(base, 3)
    hb = None if b == -1 else c.handle(b, 3)
    ht, hg = c.handle(tip, 4), c.handle(target, 5)
    for h in (hb, ht, hg):
        if h is not None:
            c.entry(h)
    element = e.kin.add_element_from_scene(g, hb, ht, hg, integer(constraints, 6))
    mapping = {h: h for h in (hb, ht, hg) if h is not None}
    cur = w.parent(ht)
    while cur is not None and cur != hb:
        mapping[cur] = cur
        if w.is_joint(cur):
            name = w.object_name(cur)
            e.joints.setdefault(name, w.joint_position(cur))
            e.modes.setdefault(name, IK)
        cur = w.parent(cur)
    return element, mapping


def add_element_from_scene_46(c: Caller, *args: Any) -> tuple[int, dict[int, int], dict[int, int]]:
    """4.6's addElementFromScene: the element and both maps (scene->IK, IK->scene)."""
    element, mapping = add_element_from_scene(c, *args)
    return element, mapping, {v: k for k, v in mapping.items()}


def _pair(value: Any, position: int) -> tuple[float, float]:
    v = numbers(value)
    if len(v) < 2:
        raise SimError(f"argument {position}: a table of 2 numbers expected")
    return v[0], v[1]


def set_element_precision(c: Caller, env: Any, group: Any, element: Any, precision: Any) -> None:
    e = _env(c, env)
    try:
        e.kin.set_element_precision(_group(e, group), integer(element, 3), *_pair(precision, 4))
    except (KeyError, IndexError) as exc:
        raise SimError(str(exc).strip("'\"")) from None


def set_element_weights(c: Caller, env: Any, group: Any, element: Any, weights: Any) -> None:
    e = _env(c, env)
    try:
        e.kin.set_element_weights(_group(e, group), integer(element, 3), *_pair(weights, 4))
    except KeyError as exc:
        raise SimError(str(exc).strip("'\"")) from None


def set_element_constraints(c: Caller, env: Any, group: Any, element: Any, bits: Any) -> None:
    e = _env(c, env)
    try:
        e.kin.set_element_constraints(_group(e, group), integer(element, 3), integer(bits, 4))
    except KeyError as exc:
        raise SimError(str(exc).strip("'\"")) from None


# -- joints of an environment --------------------------------------------------------------------
def get_joint_position(c: Caller, env: Any, joint: Any) -> float:
    e = _env(c, env)
    name = _joint_name(c, e, joint)
    return float(e.joints.get(name, c.world.joint_position(name)))


def set_joint_position(c: Caller, env: Any, joint: Any, value: Any) -> None:
    e = _env(c, env)
    e.joints[_joint_name(c, e, joint)] = number(value, 3)


def get_joint_mode(c: Caller, env: Any, joint: Any) -> int:
    e = _env(c, env)
    return e.modes.get(_joint_name(c, e, joint), IK)


def set_joint_mode(c: Caller, env: Any, joint: Any, mode: Any) -> None:
    e = _env(c, env)
    m = integer(mode, 3)
    if m not in (PASSIVE, IK, DEPENDENT):
        raise SimError(f"argument 3: unknown joint mode {m}")
    e.modes[_joint_name(c, e, joint)] = m


# -- solving -------------------------------------------------------------------------------------
def _solve(c: Caller, e: Env, g: int) -> tuple[int, dict[str, float]]:
    names = e.kin.joint_names(g)
    only = [n for n in names if e.modes.get(n, IK) == IK]
    start = {n: e.joints.get(n, c.world.joint_position(n)) for n in names}
    found = e.kin.solve(g, start, only) if only else None
    if found is None:
        return NOT_PERFORMED, {}
    values, reached = found
    e.joints.update(values)
    return (SUCCESS if reached else FAIL), values


def _sync_in(c: Caller, e: Env, g: int) -> None:
    for n in e.kin.joint_names(g):
        e.joints[n] = c.world.joint_position(n)


def _write_out(c: Caller, values: dict[str, float]) -> None:
    for name, value in values.items():
        c.world.apply_ik(name, value)


def handle_ik_group(c: Caller, env: Any, group: Any = None) -> int:
    """simIK.handleIkGroup (4.2-4.5): one resolution inside the environment."""
    e = _env(c, env)
    groups = list(e.kin.groups) if group is None or integer(group, 2) < 0 else [_group(e, group)]
    results = [_solve(c, e, g)[0] for g in groups]
    return results[0] if len(results) == 1 else sum(r != NOT_PERFORMED for r in results)


def apply_scene_to_ik_environment(c: Caller, env: Any, group: Any) -> None:
    e = _env(c, env)
    _sync_in(c, e, _group(e, group))


def apply_ik_environment_to_scene(
    c: Caller, env: Any, group: Any, only_when_successful: Any = False
) -> int:
    """The scene's joints in, one resolution, the result written to the scene's joints."""
    e = _env(c, env)
    g = _group(e, group)
    _sync_in(c, e, g)
    result, values = _solve(c, e, g)
    if result == SUCCESS or (result == FAIL and not only_when_successful):
        _write_out(c, values)
    return result


def handle_group(c: Caller, env: Any, group: Any, opts: Any = None) -> tuple[int, int, list]:
    """simIK.handleGroup (4.6): result, calc flags and the precision reached {linear,
    angular}; ``syncWorlds`` copies the scene in and the result out (a failed resolution only
    with ``allowError``)."""
    e = _env(c, env)
    g = _group(e, group)
    o = options(opts) if opts is not None else {}
    sync = bool(o.get("syncWorlds", False))
    if sync:
        _sync_in(c, e, g)
    result, values = _solve(c, e, g)
    if sync and (result == SUCCESS or (result == FAIL and o.get("allowError", False))):
        _write_out(c, values)
    flags = {SUCCESS: 0, FAIL: CONSTANTS["calc_notwithintolerance"]}.get(result, 1)
    lin, ang = e.kin.tip_errors(g, e.joints)
    return result, flags, [lin, ang]


def find_config(
    c: Caller,
    env: Any,
    group: Any,
    joints: Any,
    threshold: Any = 0.1,
    max_time: Any = 0.5,
    metric: Any = None,
    callback: Any = None,
    aux: Any = None,
    joint_options: Any = None,
    lows: Any = None,
    ranges: Any = None,
) -> list[float] | None:
    """simIK.getConfigForTipPose / findConfig: joint values that put the tips on their targets
    (a seeded random search refined by IK), accepted by the script's callback when it gives one;
    nil when none is found. The environment and the scene are left as they were."""
    e = _env(c, env)
    g = _group(e, group)
    names = [_joint_name(c, e, j, 3) for j in table(joints)]
    kw: dict[str, Any] = {"threshold": number(threshold if threshold is not None else 0.1, 4)}
    if metric is not None:
        kw["metric"] = tuple(numbers(metric))
    if lows:
        kw["lows"] = numbers(lows)
    if ranges:
        kw["ranges"] = numbers(ranges)
    if callback is not None:
        if not callable(callback):
            raise SimError("argument 7: function expected")
        state = getattr(getattr(c, "run", None), "state", None)  # a Lua caller's state
        to_script = state.to_lua if state is not None else list
        kw["accept"] = lambda config: bool(callback(to_script(config), aux))
    try:
        found = e.kin.config_for_tip_pose(g, names, **kw)
    except KeyError as exc:
        raise SimError(str(exc).strip("'\"")) from None
    return None if found is None else [float(v) for v in found]


# -- the 3.x sim.* IK setters (on the groups saved with the scene) -------------------------------
def sim_set_ik_group_properties(
    c: Caller, group: Any, method: Any, iterations: Any, damping: Any, *rest: Any
) -> int | None:
    """sim.setIkGroupProperties (V-REP 3.x): calculation method, iterations, damping."""
    kin = IkEnvironment(c.world, c.world.kinematics.groups)
    m = integer(method, 2)
    if m not in METHODS:
        raise SimError(f"argument 2: unknown calculation method {m}")
    try:
        kin.set_group_calculation(
            integer(group, 1), METHODS[m], number(damping, 4), integer(iterations, 3)
        )
    except KeyError as exc:
        raise SimError(str(exc).strip("'\"")) from None
    return c.done


def sim_set_ik_element_properties(
    c: Caller,
    group: Any,
    tip: Any,
    constraints: Any,
    precision: Any = None,
    weight: Any = None,
    *rest: Any,
) -> int | None:
    """sim.setIkElementProperties (V-REP 3.x): the element whose tip is ``tip``."""
    kin = IkEnvironment(c.world, c.world.kinematics.groups)
    g, h = integer(group, 1), c.handle(tip, 2)
    try:
        elements = kin.groups[g].group.elements
    except KeyError:
        raise SimError(f"argument 1: no IK group with handle {g}") from None
    index = next((k + 1 for k, el in enumerate(elements) if el.tip == h), None)
    if index is None:
        raise SimError(f"argument 2: IK group {g} has no element with tip {h}")
    kin.set_element_constraints(g, index, integer(constraints, 3))
    if precision is not None:
        kin.set_element_precision(g, index, *_pair(precision, 4))
    if weight is not None:
        kin.set_element_weights(g, index, *_pair(weight, 5))
    return c.done
