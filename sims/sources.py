"""Recording sources: what turns a ClipSpec into "drive this World and record it".

A source kind is a function ``plan(spec) -> RecordingPlan``, registered by an import path
("module:function") so that worker processes (spawn/forkserver) can import it themselves. The
built-in kind "scenario" reads the scenario registry; see the sims.clips docstring for how to
add a kind (e.g. "script" for course scripts run against the remote API).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from sims.clips import ClipSpec
    from sims.recording import Recorder
    from sims.world import World

SOURCE_KINDS: dict[str, str] = {"scenario": "sims.sources:scenario_plan"}


@dataclass
class RecordingPlan:
    """Everything needed to key, run and describe one clip; built in parent and worker alike.

    ``hash_files`` are the files whose bytes identify this source's behaviour (the scenario
    file, a course script...); the engine's own files are added by sims.cache.
    ``drive(world, record)`` runs inside a started Recorder and may simply return early.
    """

    scene: str
    seed: int
    duration: float
    description: str
    source_path: str
    params: dict[str, Any]
    hash_files: list[str]
    drive: Callable[[World, Recorder], None]
    scene_options: dict[str, Any] = field(default_factory=dict)
    follow: str | None = None
    joints: tuple[str, ...] = ()
    joint_quantity: str = "angle"
    extra_columns: tuple[str, ...] = ()


def register_source_kind(kind: str, target: str) -> None:
    """Register ``target`` ("package.module:function") as the plan function for ``kind``."""
    if ":" not in target:
        raise ValueError(f"source target must be 'module:function', not {target!r}")
    SOURCE_KINDS[kind] = target


def source_target(kind: str) -> str:
    if kind not in SOURCE_KINDS:
        raise KeyError(f"unknown clip kind {kind!r} (known: {', '.join(sorted(SOURCE_KINDS))})")
    return SOURCE_KINDS[kind]


def load_plan_function(target: str) -> Callable[[ClipSpec], RecordingPlan]:
    module, _, name = target.partition(":")
    return getattr(importlib.import_module(module), name)


def scenario_plan(spec: ClipSpec) -> RecordingPlan:
    """The built-in kind: ``spec.scenario`` names a scenario in sims/scenarios/."""
    return plan_scenario(spec.scenario, spec.seed, spec.params)


def plan_scenario(
    name: str, seed: int | None = None, params: dict[str, Any] | None = None
) -> RecordingPlan:
    from sims.scenarios import get_scenario

    scenario = get_scenario(name)
    resolved = scenario.resolve_params(params)
    return RecordingPlan(
        scene=scenario.scene,
        seed=scenario.seed if seed is None else seed,
        duration=scenario.duration_for(resolved),
        description=scenario.description,
        source_path=scenario.source_path,
        params=resolved,
        hash_files=[scenario.source_path],
        drive=lambda world, rec: scenario.run(world, resolved, rec),
        scene_options=dict(scenario.scene_options),
        follow=scenario.follow,
        joints=scenario.joints,
        joint_quantity=scenario.joint_quantity,
        extra_columns=scenario.extra_columns,
    )
