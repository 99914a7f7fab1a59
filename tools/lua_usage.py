"""Which ``sim`` functions the course scenes' scripts call: the table in docs/lua.md (a dev tool,
outside the runtime package: ``python -m sims.lua functions FOLDER`` runs it from a checkout).

``scan(folder)`` loads every scene file under ``folder`` (loading runs nothing), strips Lua
comments from each child and customization script (the main script is CoppeliaSim's default,
which this emulation replaces) and collects the calls of ``sim.*``, ``sim*`` (V-REP 3.x names,
folded onto their 4.x names) and ``simUI.*``-style plug-in functions.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from sims.simapi.table import FUNCTIONS, OLD_NAMES

CALL = re.compile(r"\b(sim[A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)?)\s*\(")
LONG_COMMENT = re.compile(r"--\[(=*)\[.*?\]\1\]", re.S)
LINE_COMMENT = re.compile(r"--[^\n]*")


@dataclass(frozen=True)
class Usage:
    function: str  # 4.x name: "sim.getObjectHandle", "simUI.create", "simExtOMPL_compute"
    scenes: tuple[str, ...]
    emulated: bool


def canonical(name: str) -> str:
    """``simGetObjectHandle`` -> ``sim.getObjectHandle``; dotted names and plug-ins stay."""
    if "." in name:
        return name
    if name in OLD_NAMES:
        return OLD_NAMES[name]
    if name.startswith("simExt") or name in ("sim",):
        return name
    if re.match(r"sim[A-Z]", name):
        return "sim." + name[3].lower() + name[4:]
    return name


def is_emulated(function: str) -> bool:
    return function in FUNCTIONS


def scene_files(folder: Path) -> list[Path]:
    files = list(folder.rglob("*.ttt")) + list(folder.rglob("*.simscene.xml"))
    return sorted(files)


def calls_in(text: str) -> set[str]:
    text = LINE_COMMENT.sub("", LONG_COMMENT.sub("", text))
    return {canonical(m.group(1)) for m in CALL.finditer(text)}


def scan(folder: Path) -> list[Usage]:
    from sims.scene.load import load_scene

    used: dict[str, set[str]] = {}
    for path in scene_files(folder):
        scene = load_scene(path)
        label = str(path.relative_to(folder))
        for script in scene.scripts:
            if script.kind == "main":
                continue
            for fn in calls_in(script.text):
                if fn.startswith("sim") and not fn.startswith("sim_"):
                    used.setdefault(fn, set()).add(label)
    rows = [Usage(fn, tuple(sorted(s)), is_emulated(fn)) for fn, s in used.items()]
    return sorted(rows, key=lambda u: (-len(u.scenes), u.function))


def markdown_table(rows: list[Usage]) -> str:
    lines = ["| function | scenes using it | emulated |", "|---|---:|---|"]
    for u in rows:
        lines.append(f"| `{u.function}` | {len(u.scenes)} | {'yes' if u.emulated else 'no'} |")
    return "\n".join(lines)
