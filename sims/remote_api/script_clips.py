"""Clips of course scripts: the ``script`` recording source kind for ``sims.clips``.

``ClipSpec(name, scenario="path/to/script.py", kind="script", params={"scene": "2w1a"})``
renders the script's run like a scenario clip (WebM, poster, CSV/JSON, SVG path). Params:
``scene`` (default: guessed from the object names the script uses), ``after`` (seconds the
world keeps running once the script ends, default 0), ``server`` (``continuous``/``temporary``,
default per scene), ``timeout`` (script time limit, s). ``spec.seed`` seeds the World and
Python's ``random`` for the script (default 0).

The clip shows simulated time (the Recorder films physics steps), so the pauses between
simulations are not in it. Its length is the script's simulated duration: ``spec.seconds`` if
given, else measured by a silent dry run in the worker that renders it (memoised per script
content in that process; never when the clip comes from the cache). The
cache key covers the script's bytes and this package's source files (``hash_files``).

Declared in ``sims.sources.SOURCE_KINDS`` (``"script"``); nothing registers it by import.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import re
from functools import lru_cache
from pathlib import Path
from typing import Any

from .client import missing_report
from .runner import DEFAULT_TIMEOUT, run_script

KIND = "script"
TARGET = "sims.remote_api.script_clips:script_plan"  # its entry in sims.sources.SOURCE_KINDS
MARGIN = 0.1  # s of clip after the measured end, so the recorder never cuts the script short

#: Object names that identify a scene in a script's text.
SCENE_NAMES = {
    "2w1a": ("2W1A", "ShoulderMotor", "ElbowMotor", "WristMotor", "LeftWheelJoint"),
    "cart": ("left_m", "right_m"),
}
JOINTS = {
    "2w1a": (("ShoulderMotor", "ElbowMotor", "WristMotor"), "angle"),
    "cart": (("left_m", "right_m"), "speed"),
}
PARAMS = ("scene", "after", "server", "timeout", "args", "keys", "stdin", "python")
#: Params naming files whose content is part of the run (and so of the clip's cache key).
FILE_PARAMS = ("keys", "stdin")


def guess_scene(text: str) -> str | None:
    """The one scene whose object names the script mentions (in quotes), else None."""
    found = [
        scene
        for scene, names in SCENE_NAMES.items()
        if any(re.search("['\"]" + re.escape(n) + "['\"#]", text) for n in names)
    ]
    return found[0] if len(found) == 1 else None


def resolve_params(script: Path, params: dict[str, Any]) -> dict[str, Any]:
    unknown = sorted(set(params) - set(PARAMS))
    if unknown:
        raise ValueError(
            f"script clips have no param {', '.join(unknown)} (known: {', '.join(PARAMS)})"
        )
    scene = params.get("scene") or guess_scene(script.read_text(encoding="utf-8", errors="replace"))
    if not scene:
        raise ValueError(f"{script.name}: cannot tell the scene from the script; set params.scene")
    args = params.get("args") or []
    if not isinstance(args, (list, tuple)) or not all(isinstance(a, str) for a in args):
        raise ValueError("params.args must be a list of strings (the script's sys.argv[1:])")
    out = {
        "scene": str(scene),
        "after": float(params.get("after", 0.0) or 0.0),
        "server": params.get("server"),
        "timeout": float(params.get("timeout", DEFAULT_TIMEOUT) or DEFAULT_TIMEOUT),
        "args": [str(a) for a in args],
        "python": str(params["python"]) if params.get("python") else None,
    }
    for key in FILE_PARAMS:
        value = params.get(key)
        if value:
            path = Path(value).expanduser()
            if not path.is_file():
                raise ValueError(f"params.{key}: no such file: {value}")
            out[key] = str(path.resolve())
        else:
            out[key] = None
    if out["keys"]:
        from sims.lua.keys import load

        load(out["keys"])  # a malformed key file fails here, naming its line
    return out


def clock_limit(seconds: float) -> float:
    """A clip's limit on the script's clock (simulated s): its length plus a margin, since the
    script's clock also runs while its simulation is stopped (docs/clips.md, "Limits")."""
    return round(seconds * 1.5 + 10.0, 3)


def _wall_left(record: Any) -> float | None:
    """The clip's wall-clock safety net still left (the Recorder's deadline), if it has one."""
    import time

    deadline = getattr(record, "deadline", None)
    return None if deadline is None else max(0.1, deadline - time.monotonic())


def _api_name(script: Path) -> str:
    from .zmq import uses_zmq

    return "ZeroMQ" if uses_zmq(script) else "legacy"


def script_plan(spec: Any):
    """``plan(spec)`` for sims.clips: ``spec.scenario`` is the script's path."""
    from sims.recording import RecordingPlan

    script = Path(spec.scenario).expanduser().resolve()
    if not script.is_file():
        raise FileNotFoundError(f"no such script: {spec.scenario}")
    params = resolve_params(script, dict(spec.params))
    if spec.seconds is not None and "timeout" not in spec.params:
        params["timeout"] = clock_limit(float(spec.seconds))
    seed = 0 if spec.seed is None else int(spec.seed)
    duration, dry_run = 0.0, None
    if spec.seconds is not None:
        duration = float(spec.seconds)
    else:
        digest = hashlib.sha256(script.read_bytes())
        for key in FILE_PARAMS:
            if params[key]:
                digest.update(Path(params[key]).read_bytes())
        frozen = tuple(sorted((k, repr(v)) for k, v in params.items()))

        def dry_run() -> float:  # only when the clip is rendered (RecordingPlan.length)
            return measure(str(script), digest.hexdigest(), seed, frozen)

    joints, quantity = JOINTS.get(params["scene"], ((), "angle"))

    def drive(world: Any, record: Any) -> None:
        drive_script(world, record, script, params, seed)

    return RecordingPlan(
        scene=params["scene"],
        seed=seed,
        duration=duration,
        description=(  # the scene file's name only: no checkout path in pages or the cache
            f"Script {script.name}, run unchanged through the {_api_name(script)} "
            f"remote API emulation (scene {Path(params['scene']).name}, seed {seed})"
        ),
        source_path=str(script),
        params=params,
        hash_files=[str(script), *run_files(params)],  # the code: clip_cache.clip_key
        drive=drive,
        joints=joints,
        joint_quantity=quantity,
        extra_columns=("simulation",),
        measure=dry_run,
    )


def run_files(params: dict[str, Any]) -> list[str]:
    """The files besides the script that a run reads (key file, standard input)."""
    return [params[k] for k in FILE_PARAMS if params.get(k)]


@contextlib.contextmanager
def run_inputs(params: dict[str, Any]):
    """The key file and standard input of a run, in place while the block runs."""
    import sys

    from sims.lua import keys

    keys.configure(keys.load(params["keys"]) if params.get("keys") else None)
    saved = sys.stdin
    feed = (
        open(params["stdin"], encoding="utf-8")  # noqa: SIM115 (closed below)
        if params.get("stdin")
        else io.StringIO("")
    )
    sys.stdin = feed
    try:
        yield
    finally:
        sys.stdin = saved
        feed.close()
        keys.configure(None)


def run_options(params: dict[str, Any]) -> dict[str, Any]:
    """``run_script`` keyword arguments from resolved params."""
    return {
        "server": params["server"],
        "after": params["after"],
        "timeout": params["timeout"],
        "argv": params.get("args") or (),
        **({"python": params["python"]} if params.get("python") else {}),
    }


@lru_cache(maxsize=64)
def measure(script: str, digest: str, seed: int, frozen: tuple) -> float:
    """Simulated seconds a silent run of the script takes (plus a small margin). ``digest``
    covers the script and its input files; ``frozen`` is the resolved params (memo key)."""
    del digest  # part of the memo key only
    params = resolve_params(Path(script), {k: _unrepr(v) for k, v in frozen})
    sink = io.StringIO()
    with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink), run_inputs(params):
        result = run_script(
            script,
            params["scene"],
            seed=seed,
            trace=False,
            stderr=sink,
            **run_options(params),
        )
    if not result.ok:
        raise RuntimeError(result.message or f"{Path(script).name} exited with {result.exit_code}")
    return max(result.sim_time, 0.0) + MARGIN


class _Lines(io.TextIOBase):
    """A text stream that turns each printed line into a recorder event."""

    def __init__(self, record: Any, kind: str):
        self.record, self.kind, self.buffer_ = record, kind, ""

    def writable(self) -> bool:
        return True

    def write(self, text: str) -> int:
        self.buffer_ += text
        while "\n" in self.buffer_:
            line, self.buffer_ = self.buffer_.split("\n", 1)
            self.record.note(self.kind, line=line)
        return len(text)

    def flush_rest(self) -> None:
        if self.buffer_:
            self.record.note(self.kind, line=self.buffer_)
            self.buffer_ = ""


def drive_script(world: Any, record: Any, script: Path, params: dict[str, Any], seed: int) -> Any:
    """Run the script on the recorder's World; its output lines become clip events."""

    def on_pass(sim: Any) -> None:
        record.set("simulation", float(sim.starts))

    out, err = _Lines(record, "stdout"), _Lines(record, "stderr")
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), run_inputs(params):
        result = run_script(
            script,
            params["scene"],
            seed=seed,
            **run_options(params),
            world=world,
            on_pass=on_pass,
            trace=False,
            stderr=err,
            wall_timeout=_wall_left(record),
        )
    for line in missing_report(result.missing):  # the clip's build log says what was lacking
        print(line, file=err)
    out.flush_rest()
    err.flush_rest()
    record.note("script ended", exit_code=result.exit_code, simulated=round(result.sim_time, 3))
    if result.final_state != "running" and record.taken > record.frames // 2:
        # CoppeliaSim films simulations only: once the last one has stopped (the scene is back
        # in its initial pose), the clip ends here instead of idling to its planned length
        record.done = True
    if not result.ok:
        raise RuntimeError(result.message or f"{script.name} exited with {result.exit_code}")
    return result


def _unrepr(text: str) -> Any:
    import ast

    return ast.literal_eval(text)
