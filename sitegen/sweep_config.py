"""``sims: sweeps:`` in sitegen.yml: sweeps built like clips (sitegen/sweeps_pages.py).

Kept apart from sitegen/config.py (which calls :func:`parse_sweeps`) because a sweep has its own
dozen keys. Every problem is a diagnostic at the key's line, as for the rest of sitegen.yml.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sitegen.config_paths import inside_project

if TYPE_CHECKING:
    import yaml

    from located.yamlwalk import Walker

EXECUTORS = ("local", "ray")
_NAME = re.compile(r"^[a-z0-9][a-z0-9_-]*$")
_ARG = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_SWEEP = {
    "name": "str",
    "title": "str",
    "script": "str",
    "scene": "str",
    "seeds": "str",
    "grid": "map",
    "args": "str",
    "seed": "int",
    "seconds": "num",
    "timeout": "num",
    "key": "str",
    "order": "str",
    "best": "int",
    "x": "str",
    "y": "str",
}


@dataclass(frozen=True)
class SweepConfig:
    """One sweep shown as a page: its runs, how to rank them, what to plot."""

    name: str
    script: Path
    scene: str
    title: str | None = None
    seeds: str | None = None  # "0:50", as --seeds
    grid: tuple[tuple[str, tuple[str, ...]], ...] = ()
    args: Path | None = None  # an argument file (CSV), as --args-file
    seed: int = 0
    seconds: float | None = None  # cut each run after this many simulated seconds
    timeout: float | None = None  # per run, wall and script clock (default 300)
    key: str | None = None  # the column that ranks runs (a RESULT key or final_x...)
    order: str = "max"  # max: the largest key is best; min: the smallest
    best: int = 3  # best runs shown as clips (0: none)
    x: str = "final_x"  # the scatter plot's columns
    y: str = "final_y"


def parse_sweeps(ck: Walker, node: yaml.Node, root: Path) -> tuple[SweepConfig, ...]:
    from located.yaml import to_python

    out: list[SweepConfig] = []
    names: set[str] = set()
    for i, item in enumerate(ck.sequence(node, "sims.sweeps")):
        where = f"sims.sweeps[{i}]"
        nodes = ck.keys(item, where, _SWEEP)
        v: dict[str, Any] = {}
        for key, value_node in nodes.items():
            if key == "seeds" and isinstance(value_node.value, str):  # YAML 1.1 reads 0:50 as 50
                v[key] = value_node.value
            elif _SWEEP[key] != "map":
                value = ck.value(value_node, f"{where}.{key}", _SWEEP[key])
                if value is not None:
                    v[key] = value
        missing = [k for k in ("name", "script", "scene") if k not in v]
        if missing:
            ck.fail(item, f"{where}.{missing[0]}", "is required")
            continue
        problem = _problem(v, names)
        if problem:
            ck.fail(nodes.get(problem[0], item), f"{where}.{problem[0]}", problem[1])
            continue
        if "grid" in nodes:
            grid = _grid(to_python(nodes["grid"]))
            if isinstance(grid, str):
                ck.fail(nodes["grid"], f"{where}.grid", grid)
                continue
            v["grid"] = grid
        if "seeds" not in v and "grid" not in v and "args" not in v:
            ck.fail(item, where, "give seeds, grid or args (the runs of the sweep)")
            continue
        if not inside_project(ck, nodes, v, ("script", "args", "scene"), where + ".", root):
            continue
        names.add(v["name"])
        v["script"] = root / v["script"]
        if "args" in v:
            v["args"] = root / v["args"]
        out.append(SweepConfig(**v))
    return tuple(out)


def _problem(v: dict[str, Any], names: set[str]) -> tuple[str, str] | None:
    if not _NAME.match(v["name"]):
        return "name", "must be lower-case letters, digits, - and _ (it names files and a page)"
    if v["name"] in names:
        return "name", f"{v['name']!r} is used by another sweep"
    for key in ("seconds", "timeout"):
        if key in v and not 0 < v[key] < float("inf"):
            return key, "must be a positive number of seconds"
    if v.get("order", "max") not in ("max", "min"):
        return "order", "must be max or min"
    if not 0 <= v.get("best", 3) <= 20:
        return "best", "must be a whole number from 0 to 20"
    if "seeds" in v:
        from sims.sweeps.plan import parse_seeds

        try:
            if len(parse_seeds(v["seeds"])) > 100_000:
                return "seeds", "more than 100000 runs: run it with sitegen remote-api sweep"
        except Exception as exc:  # LocatedError: its message, at this key's line
            return "seeds", getattr(exc, "message", str(exc))
    return None


def _grid(value: Any) -> tuple[tuple[str, tuple[str, ...]], ...] | str:
    """``{name: [a, b], other: "x,y"}`` in the order written; a message when malformed."""
    if not isinstance(value, dict) or not value:
        return "must map argument names to lists of values"
    out = []
    for name, values in value.items():
        if not isinstance(name, str) or not _ARG.match(name):
            return f"{name!r} is not an argument name (letters, digits, _)"
        if isinstance(values, str):
            values = [x.strip() for x in values.split(",")]
        if not isinstance(values, list) or not values:
            return f"{name}: give a list of values"
        if any(isinstance(x, (dict, list)) or x is None or x == "" for x in values):
            return f"{name}: values must be numbers or text"
        out.append((name, tuple(repr(x) if isinstance(x, float) else str(x) for x in values)))
    return tuple(out)
