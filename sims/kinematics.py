"""Inverse kinematics of a World: the IK groups saved with the scene, solved as CoppeliaSim does.

An IK group holds elements; each element drives a *tip* dummy onto its linked *target* dummy
over the joints between the element's base and the tip that are in IK mode (or hybrid: IK sets
their position target and their motors drive them under dynamics). Each resolution runs the
group's iterations of its calculation method (pseudo-inverse, or damped least squares with its
damping) on the stacked Jacobian of all elements, rows weighted by the element's position and
orientation weights and columns by each joint's IK weight, keeping joints within their limits.
The constraints (x, y, z, alpha-beta, gamma) select which rows are matched, expressed in the
element's reference frame (its base, or the world).

Written here rather than taken from a library: the solver must work on the World's own object
tree (frames read from pybullet, joint modes and limits from the scene) and reproduce
CoppeliaSim's per-pass behaviour (a few iterations each pass, a result code per group); the
numerics are numpy's (``lstsq`` / ``solve``). ``config_for_tip_pose`` is CoppeliaSim's
randomised search (sim.getConfigForTipPose), seeded from the World's seed so runs repeat.

The main script's pass (``main_script_pass``) handles every group that is not explicitly
handled, as CoppeliaSim's default main script does with
``sim.handleIkGroup(sim.handle_all_except_explicit)``.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from sims.scene.model import IkElement, IkGroup
from sims.scene.model_mech import IK_ALPHA_BETA, IK_GAMMA, IK_X, IK_Y, IK_Z

HANDLE_ALL, HANDLE_ALL_EXCEPT_EXPLICIT = -2, -3  # sim.handle_all, sim.handle_all_except_explicit
NOT_PERFORMED, SUCCESS, FAIL = 0, 1, 2  # sim.ikresult_*
GROUP_HANDLES = 2030003  # CoppeliaSim numbers IK groups from here


@dataclass
class Chain:
    """One element's joints (base to tip) and the fixed transforms between them, read from the
    World's current pose: ``fk(q)`` gives the tip frame for any joint values."""

    joints: list[str]
    kinds: list[str]
    start: np.ndarray  # the first joint's own frame (4x4, world)
    links: list[np.ndarray]  # joint k's moved frame -> next joint's own frame (last: the tip)
    q: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    weights: np.ndarray

    def frames(self, q: np.ndarray) -> tuple[list[np.ndarray], np.ndarray]:
        """Each joint's own frame and the tip's frame (4x4, world) at joint values ``q``."""
        own, cur = [], self.start
        for k, kind in enumerate(self.kinds):
            own.append(cur)
            cur = cur @ _move(kind, q[k]) @ self.links[k]
        return own, cur


@dataclass
class GroupState:
    """An IK group of the World: the saved record (World handles) and what scripts changed."""

    group: IkGroup
    explicit: bool
    enabled: bool
    last: int = NOT_PERFORMED


@dataclass
class Kinematics:
    """The IK groups of one World (``world.kinematics``)."""

    world: Any
    groups: dict[int, GroupState] = field(default_factory=dict)

    @classmethod
    def of(cls, world: Any, scene: Any) -> Kinematics:
        """The scene's IK groups with their object handles turned into the World's."""
        table = {o.handle: o.name for o in getattr(scene, "objects", ())}

        def h(handle: int | None) -> int | None:
            return None if handle is None else world.handle(table.get(handle, ""))

        out = cls(world)
        for k, g in enumerate(getattr(scene, "ik_groups", ())):
            elements = tuple(
                replace(e, tip=h(e.tip) or 0, base=h(e.base), reference=h(e.reference))
                for e in g.elements
            )
            handle = g.handle if g.handle >= 0 else GROUP_HANDLES + k
            grp = replace(g, handle=handle, elements=elements)
            out.groups[handle] = GroupState(grp, g.explicit, g.enabled)
        return out

    # -- the API the sim.* bindings call ------------------------------------------------------
    def group_handle(self, name: str) -> int:
        """sim.getIkGroupHandle: KeyError when the scene has no such group."""
        base = name.split("#")[0] if name.endswith("#") else name
        for handle, state in self.groups.items():
            if state.group.name in (name, base):
                return handle
        raise KeyError(f"no IK group named {name!r}")

    def set_explicit_handling(self, group: int, explicit: bool) -> None:
        self._state(group).explicit = bool(explicit)

    def explicit_handling(self, group: int) -> bool:
        return self._state(group).explicit

    def handle(self, group: int) -> int:
        """sim.handleIkGroup: solve and apply one group (its result code), or every group
        (``HANDLE_ALL``) / every group not explicitly handled (``HANDLE_ALL_EXCEPT_EXPLICIT``):
        the number of groups performed."""
        if group in (HANDLE_ALL, HANDLE_ALL_EXCEPT_EXPLICIT):
            done = 0
            for state in self.groups.values():
                if group == HANDLE_ALL_EXCEPT_EXPLICIT and state.explicit:
                    continue
                if self._solve_and_apply(state) != NOT_PERFORMED:
                    done += 1
            return done
        return self._solve_and_apply(self._state(group))

    def main_script_pass(self) -> int:
        """What the default main script does each pass (3.x and 4.x)."""
        return self.handle(HANDLE_ALL_EXCEPT_EXPLICIT) if self.groups else 0

    def config_for_tip_pose(
        self,
        group: int,
        joints: list[int | str],
        threshold: float = 0.65,
        trials: int = 100,
        metric: tuple[float, float, float, float] = (1.0, 1.0, 1.0, 0.1),
        lows: list[float] | None = None,
        ranges: list[float] | None = None,
        accept: Any = None,
    ) -> list[float] | None:
        """sim.getConfigForTipPose: random joint values (within limits, or ``lows`` +
        ``ranges``) whose tip lies within ``threshold`` (the metric-weighted distance) of the
        target are refined by IK; the first that reaches the target (and that ``accept``, a
        script's validation callback, takes when given), or None."""
        state = self._state(group)
        names = [self.world.object_name(j) for j in joints]
        rng = random.Random(self.world.seed * 7919 + self.world.steps)
        elements = [e for e in state.group.elements if e.enabled]
        chains = [self._chain(e, only=names) for e in elements]
        if not chains or any(c is None for c in chains):
            return None
        lo = np.array(lows) if lows else None
        for _ in range(max(1, trials)):
            q = {}
            for k, n in enumerate(names):
                j = self.world.joint(n)
                a = lo[k] if lo is not None else (j.lower if j.lower is not None else -math.pi)
                if ranges:
                    b = a + ranges[k]
                else:
                    b = j.upper if j.upper is not None else math.pi
                q[n] = rng.uniform(a, b)
            if all(
                _metric(c, e, self.world, q, metric) <= threshold
                for c, e in zip(chains, elements, strict=True)
            ):
                found = self._solve(state.group, elements, q, iterations=40, only=names)
                if found is not None and found[1]:
                    config = [found[0][n] for n in names]
                    if accept is None or accept(config):
                        return config
        return None

    # -- solving ------------------------------------------------------------------------------
    def _state(self, group: int) -> GroupState:
        if group not in self.groups:
            raise KeyError(f"no IK group with handle {group}")
        return self.groups[group]

    def _solve_and_apply(self, state: GroupState) -> int:
        if not state.enabled:
            return NOT_PERFORMED
        elements = [e for e in state.group.elements if e.enabled]
        found = self._solve(state.group, elements, None)
        if found is None:
            state.last = NOT_PERFORMED
            return NOT_PERFORMED
        values, reached = found
        g = state.group
        keep = not reached and (
            g.restore_if_position_not_reached or g.restore_if_orientation_not_reached
        )
        if not keep:  # CoppeliaSim applies a partial result unless asked to restore
            for name, value in values.items():
                self.world.apply_ik(name, value)
        state.last = SUCCESS if reached else FAIL
        return state.last

    def _chain(self, e: IkElement, only: list[str] | None = None) -> Chain | None:
        w = self.world
        names = []
        cur = w.parent(e.tip) if e.tip else None
        while cur is not None and cur != e.base:
            if w.kind(cur) == "joint":
                name = w.object_name(cur)
                j = w.joint(name)
                if only is not None:
                    takes_part = name in only
                else:
                    takes_part = e.all_joints or w.joint_in_ik(name)
                if takes_part and j.kind in ("revolute", "prismatic"):
                    names.append(name)
            cur = w.parent(cur)
        if not names or self._target(e) is None:
            return None
        names.reverse()
        frames = [_matrix(w.object_pose(n)) for n in names]
        q = np.array([w.joint_position(n) for n in names])
        kinds = [w.joint(n).kind for n in names]
        tip = _matrix(w.object_pose(e.tip))
        links = []
        for k in range(len(names)):
            nxt = frames[k + 1] if k + 1 < len(names) else tip
            links.append(np.linalg.inv(frames[k] @ _move(kinds[k], q[k])) @ nxt)
        refs = [w.joint(n) for n in names]
        lower = np.array([-np.inf if r.lower is None else r.lower for r in refs])
        upper = np.array([np.inf if r.upper is None else r.upper for r in refs])
        weights = np.array([w.joint_ik_weight(n) for n in names])
        return Chain(names, kinds, frames[0], links, q, lower, upper, weights)

    def _target(self, e: IkElement) -> int | None:
        if e.target is not None:
            return e.target
        return self.world.linked_dummy(e.tip) if e.tip else None

    def _solve(
        self,
        group: IkGroup,
        elements: list[IkElement],
        start: dict[str, float] | None,
        iterations: int | None = None,
        only: list[str] | None = None,
    ) -> tuple[dict[str, float], bool] | None:
        """Joint values that bring the tips toward their targets from the current values (or
        ``start``) and whether every tip is within its precision; None without a chain."""
        chains = [(e, self._chain(e, only)) for e in elements]
        chains = [(e, c) for e, c in chains if c is not None]
        if not chains:
            return None
        names = sorted({n for _, c in chains for n in c.joints})
        index = {n: i for i, n in enumerate(names)}
        q = np.array([self.world.joint_position(n) for n in names])
        if start:
            q = np.array([start.get(n, q[i]) for i, n in enumerate(names)])
        lower, upper, weights = np.full(len(q), -np.inf), np.full(len(q), np.inf), np.ones(len(q))
        for _, c in chains:
            for k, n in enumerate(c.joints):
                lower[index[n]], upper[index[n]] = c.lower[k], c.upper[k]
                weights[index[n]] = c.weights[k]
        targets = [_matrix(self.world.object_pose(self._target(e))) for e, _ in chains]
        for _ in range(iterations or group.iterations):
            rows, errors, reached = [], [], True
            for (e, c), target in zip(chains, targets, strict=True):
                qc = np.array([q[index[n]] for n in c.joints])
                jac, err, ok = _element_rows(e, c, qc, target, self._reference(e))
                full = np.zeros((len(err), len(q)))
                for k, n in enumerate(c.joints):
                    full[:, index[n]] = jac[:, k]
                rows.append(full)
                errors.append(err)
                reached &= ok
            if reached:
                return dict(zip(names, q.tolist(), strict=True)), True
            jac, err = np.vstack(rows), np.concatenate(errors)
            step = _step(jac * weights, err, group) * weights
            q = np.clip(q + step, lower, upper)
        reached = all(
            _element_rows(e, c, np.array([q[index[n]] for n in c.joints]), t, self._reference(e))[2]
            for (e, c), t in zip(chains, targets, strict=True)
        )
        return dict(zip(names, q.tolist(), strict=True)), reached

    def _reference(self, e: IkElement) -> np.ndarray:
        ref = e.reference if e.reference is not None else e.base
        return np.eye(3) if ref is None else _matrix(self.world.object_pose(ref))[:3, :3]


def _element_rows(
    e: IkElement, c: Chain, q: np.ndarray, target: np.ndarray, ref: np.ndarray
) -> tuple[np.ndarray, np.ndarray, bool]:
    """The element's Jacobian rows, error rows (in its reference frame) and whether it is
    within its precision, at joint values ``q``."""
    own, tip = c.frames(q)
    cols_lin, cols_ang = [], []
    for frame, kind in zip(own, c.kinds, strict=True):
        axis, origin = frame[:3, 2], frame[:3, 3]
        if kind == "prismatic":
            cols_lin.append(axis)
            cols_ang.append(np.zeros(3))
        else:
            cols_lin.append(np.cross(axis, tip[:3, 3] - origin))
            cols_ang.append(axis)
    jl, ja = ref.T @ np.array(cols_lin).T, ref.T @ np.array(cols_ang).T
    dp = ref.T @ (target[:3, 3] - tip[:3, 3])
    rot = target[:3, :3] @ tip[:3, :3].T
    dw = ref.T @ _rotation_vector(rot)
    pw, ow = e.weights
    rows, errs = [], []
    for bit, k in ((IK_X, 0), (IK_Y, 1), (IK_Z, 2)):
        if e.constraints & bit:
            rows.append(jl[k] * pw)
            errs.append(dp[k] * pw)
    if e.constraints & IK_ALPHA_BETA and e.constraints & IK_GAMMA:
        rows += [ja[k] * ow for k in range(3)]
        errs += [dw[k] * ow for k in range(3)]
    elif e.constraints & IK_ALPHA_BETA:  # the z axes aligned, free to turn about them
        zt, z = target[:3, 2], tip[:3, 2]
        err = ref.T @ np.cross(z, zt)
        rows += [ja[k] * ow for k in range(3)]
        errs += [err[k] * ow for k in range(3)]
    elif e.constraints & IK_GAMMA:
        axis = ref.T @ target[:3, 2]
        rows.append((axis @ ja) * ow)
        errs.append(float(axis @ dw) * ow)
    lin_ok = np.linalg.norm(dp * [bool(e.constraints & b) for b in (IK_X, IK_Y, IK_Z)])
    ang = np.linalg.norm(dw) if e.constraints & (IK_ALPHA_BETA | IK_GAMMA) else 0.0
    ok = lin_ok <= e.precision[0] and ang <= e.precision[1]
    if not rows:
        return np.zeros((0, len(q))), np.zeros(0), True
    return np.array(rows), np.array(errs), bool(ok)


def _step(jac: np.ndarray, err: np.ndarray, group: IkGroup) -> np.ndarray:
    if group.method == "damped_least_squares":
        lam = group.damping
        return jac.T @ np.linalg.solve(jac @ jac.T + lam * lam * np.eye(len(err)), err)
    if group.method == "jacobian_transpose":  # the step along J^T e that best reduces e
        step = jac.T @ err
        moved = jac @ step
        denominator = float(moved @ moved)
        return step * (float(err @ moved) / denominator if denominator > 1e-18 else 0.0)
    return np.linalg.lstsq(jac, err, rcond=1e-6)[0]


def _metric(c: Chain, e: IkElement, world: Any, q: dict[str, float], metric) -> float:
    """CoppeliaSim's distance between tip and target for getConfigForTipPose: x, y, z
    differences and the orientation angle, each weighted."""
    values = np.array([q.get(n, v) for n, v in zip(c.joints, c.q, strict=True)])
    tip = c.frames(values)[1]
    target = _matrix(world.object_pose(e.target or world.linked_dummy(e.tip)))
    d = target[:3, 3] - tip[:3, 3]
    angle = np.linalg.norm(_rotation_vector(target[:3, :3] @ tip[:3, :3].T))
    return math.sqrt(sum((m * v) ** 2 for m, v in zip(metric, [*d, angle], strict=True)))


def _move(kind: str, q: float) -> np.ndarray:
    m = np.eye(4)
    if kind == "prismatic":
        m[2, 3] = q
    else:
        c, s = math.cos(q), math.sin(q)
        m[:2, :2] = [[c, -s], [s, c]]
    return m


def _matrix(pose: tuple) -> np.ndarray:
    (x, y, z), (qx, qy, qz, qw) = pose
    m = np.eye(4)
    m[:3, :3] = [
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
        [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
        [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)],
    ]
    m[:3, 3] = (x, y, z)
    return m


def _rotation_vector(r: np.ndarray) -> np.ndarray:
    """Axis times angle of a rotation matrix (the orientation error)."""
    cos = max(-1.0, min(1.0, (np.trace(r) - 1) / 2))
    angle = math.acos(cos)
    v = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    if angle < 1e-9:
        return v / 2
    if math.pi - angle < 1e-6:  # half a turn: the axis from the symmetric part
        axis = np.sqrt(np.maximum(np.diag(r) + 1, 0) / 2)
        return axis * angle
    return v * (angle / (2 * math.sin(angle)))
