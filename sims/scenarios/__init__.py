"""Scenario registry: every module in this package that defines ``SCENARIO`` is one scenario.

Adding a scenario = adding one file here with ``SCENARIO = Scenario(...)`` and a
``run(world, params, record)`` function that drives the World (set joint targets, ``advance``)
and may call ``record.note(...)``/``record.set(...)``. The Recorder samples the pose and the
listed joints by itself and stops the run when the clip is long enough. Randomness must come
from ``world.seed`` (e.g. ``random.Random(world.seed)``) so a seed fixes every number.
"""

from __future__ import annotations

import importlib
import pkgutil
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from sims.recording import (
    Recorder,
    Recording,
    RecordingPlan,
    RecordingTimeout,
    drive,
    record,
)
from sims.world import World

RunFunction = Callable[[World, dict, Recorder], None]


@dataclass(frozen=True)
class Scenario:
    """A named, seeded way of driving one scene; ``duration`` may depend on the params."""

    name: str
    description: str
    scene: str
    run: RunFunction
    duration: float | Callable[[dict], float]
    seed: int = 0
    params: dict[str, Any] = field(default_factory=dict)
    joints: tuple[str, ...] = ()
    joint_quantity: str = "angle"  # "angle" (deg) or "speed" (rad/s) in the recorded samples
    extra_columns: tuple[str, ...] = ()
    scene_options: dict[str, Any] = field(default_factory=dict)
    follow: str | None = None  # object to track and film (default: the scene's robot)
    source_path: str = ""  # filled in by the registry

    def resolve_params(self, overrides: dict[str, Any] | None) -> dict[str, Any]:
        """Defaults updated by ``overrides``; an unknown key is an error (catches typos)."""
        unknown = sorted(set(overrides or {}) - set(self.params))
        if unknown:
            raise ValueError(
                f"scenario {self.name!r} has no param {', '.join(unknown)} "
                f"(known: {', '.join(sorted(self.params)) or 'none'})"
            )
        return {**self.params, **(overrides or {})}

    def duration_for(self, params: dict[str, Any]) -> float:
        return float(self.duration(params) if callable(self.duration) else self.duration)


_REGISTRY: dict[str, Scenario] | None = None


def _load() -> dict[str, Scenario]:
    global _REGISTRY
    if _REGISTRY is None:
        found: dict[str, Scenario] = {}
        for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
            module = importlib.import_module(f"{__name__}.{info.name}")
            scenario = getattr(module, "SCENARIO", None)
            if not isinstance(scenario, Scenario):
                continue
            if scenario.name in found:
                raise ValueError(f"two scenarios named {scenario.name!r}")
            source = str(Path(module.__file__ or "").resolve())
            found[scenario.name] = _with_source(scenario, source)
        _REGISTRY = dict(sorted(found.items()))
    return _REGISTRY


def _with_source(scenario: Scenario, source: str) -> Scenario:
    return replace(scenario, source_path=source)


def list_scenarios() -> list[Scenario]:
    """All scenarios, sorted by name."""
    return list(_load().values())


def get_scenario(name: str) -> Scenario:
    scenarios = _load()
    if name not in scenarios:
        raise KeyError(f"unknown scenario {name!r} (known: {', '.join(scenarios)})")
    return scenarios[name]


def run_scenario(
    name: str,
    *,
    seed: int | None = None,
    params: dict | None = None,
    seconds: float | None = None,
    fps: float = 20.0,
    on_frame: Callable[[World], None] | None = None,
    time_limit: float | None = None,
) -> Recording:
    """Run a scenario headless in a fresh World and return its samples (no rendering)."""
    deadline = None if time_limit is None else time.monotonic() + time_limit
    plan = plan_for(name, seed, params)
    return record(plan, fps=fps, seconds=seconds, on_frame=on_frame, deadline=deadline)[0]


def plan_for(
    name: str, seed: int | None = None, params: dict[str, Any] | None = None
) -> RecordingPlan:
    """The recording plan of scenario ``name`` (its own seed and params unless given)."""
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


__all__ = [
    "Scenario",
    "list_scenarios",
    "get_scenario",
    "run_scenario",
    "plan_for",
    "drive",
    "RecordingTimeout",
]
