"""The state tape of a clip: every body's pose and joint positions, one vector per frame.

A clip is simulated once without a renderer and drawn afterwards, frame range by frame range, in
other processes (sims/clip_worker.py); this tape is what passes between the two. A vector holds,
for every body in id order, its base position and quaternion and then its movable joints'
positions: exactly what a rebuilt World of the same scene needs to show that frame.
"""

from __future__ import annotations

import numpy as np

from sims.quiet import pybullet as p
from sims.world import World

Layout = list[tuple[int, tuple[int, ...]]]


class SceneChanged(RuntimeError):
    """The set of bodies changed during the run, so recorded states cannot be replayed."""


def layout_of(world: World) -> Layout:
    """Every body and its movable joints, in id order: what a state vector holds."""
    c = world.client_id
    out = []
    for i in range(p.getNumBodies(physicsClientId=c)):
        body = p.getBodyUniqueId(i, physicsClientId=c)
        joints = tuple(
            j
            for j in range(p.getNumJoints(body, physicsClientId=c))
            if p.getJointInfo(body, j, physicsClientId=c)[2] != p.JOINT_FIXED
        )
        out.append((body, joints))
    return out


def covers(world: World, layout: Layout) -> bool:
    """Does ``world`` hold every body of ``layout`` with the same joints? Extra bodies are
    allowed: a scene file's visual-only bodies, which ``World.render`` puts on their links."""
    have = dict(layout_of(world))
    return all(have.get(body) == joints for body, joints in layout)


def capture_state(world: World, layout: Layout) -> list[float]:
    c = world.client_id
    values: list[float] = []
    for body, joints in layout:
        pos, orn = p.getBasePositionAndOrientation(body, physicsClientId=c)
        values += [*pos, *orn]
        if joints:
            values += [s[0] for s in p.getJointStates(body, joints, physicsClientId=c)]
    return values


def apply_state(world: World, layout: Layout, state: np.ndarray) -> None:
    c = world.client_id
    i = 0
    for body, joints in layout:
        p.resetBasePositionAndOrientation(
            body, state[i : i + 3].tolist(), state[i + 3 : i + 7].tolist(), physicsClientId=c
        )
        i += 7
        for j in joints:
            p.resetJointState(body, j, float(state[i]), physicsClientId=c)
            i += 1
    world.moved()  # proximity readings see the new state
