"""Recording sources: what turns a ClipSpec into "drive this World and record it".

A source kind is a function ``plan(spec) -> RecordingPlan``, named in the one table
:data:`SOURCE_KINDS` by an import path ("module:function") so that worker processes
(spawn/forkserver) can import it themselves. Built in: "scenario" (the scenario registry)
and "script" (course scripts run against the remote API); see the sims.clips docstring.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import TYPE_CHECKING

from sims.recording import RecordingPlan

if TYPE_CHECKING:
    from sims.clip_spec import ClipSpec

# The one table of clip source kinds: kind -> "module:function" returning a RecordingPlan.
SOURCE_KINDS: dict[str, str] = {
    "scenario": "sims.sources:scenario_plan",  # a scenario in sims/scenarios/
    "script": "sims.remote_api.script_clips:script_plan",  # a remote API script
}

__all__ = ["SOURCE_KINDS", "RecordingPlan", "register_source_kind", "scenario_plan"]


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
    from sims.scenarios import plan_for

    return plan_for(spec.scenario, spec.seed, spec.params)
