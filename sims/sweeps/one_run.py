"""One run of a sweep: the script run as ``remote-api run`` runs it, and what it measured.

The run goes through :func:`sims.remote_api.runner.run_script`, so it is isolated exactly as a
single run is (a forked child with its own network namespace, killed at its wall-clock limit).
The caller of :func:`execute` is a long-lived worker (a local worker process or a Ray worker)
that imported everything once and loaded the scene once (:func:`warm`): each run forks from
that warm state, so a run costs what it costs in one process, and runs cannot leak state into
one another whatever order a worker takes them in.

What a run reports:

- ``RESULT key=value ...`` lines on its standard output (values that read as JSON numbers,
  ``true``/``false`` or ``null`` become those; anything else stays text);
- a JSON object written to the file named by ``$SWEEP_RESULT_FILE`` (merged after the lines);
- the scene's final state at the last simulation pass: the robot's position, heading and every
  joint's position, in CoppeliaSim's conventions (read through ``run_script``'s ``probe``, in
  the child, before a final ``stopSimulation`` puts the scene back).

A run never raises: a failure is a record with ``status`` "failed" (or "timeout") and its error.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import re
import sys
import tempfile
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from .plan import RESULT_FILE_ENV, RunSpec

RESULT_LINE = re.compile(r"^RESULT\s+(.*)$")
RESULT_PAIR = re.compile(r"([A-Za-z_][A-Za-z0-9_.\-]*)=(\"[^\"]*\"|\S*)")
LOG_TAIL = 4000  # characters of a failed run's output kept in results.jsonl
MAX_RESULT_FILE = 1 << 20


@dataclass
class RunRecord:
    """What one run gave. ``wall_seconds``, ``attempts`` and ``host`` vary from executor to
    executor and are kept out of results.csv (results.py)."""

    index: int
    seed: int
    args: dict[str, str]
    status: str  # ok, cut (stopped at --seconds as asked), failed, timeout, lost
    exit_code: int
    error: str = ""
    sim_seconds: float = 0.0
    simulations: int = 0
    results: dict[str, Any] = field(default_factory=dict)
    final: dict[str, Any] = field(default_factory=dict)
    wall_seconds: float = 0.0
    attempts: int = 1
    host: str = ""  # node name and process id of the worker that ran it
    log: str = ""  # the tail of a failed run's output

    def to_json(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> RunRecord:
        return cls(**data)

    @property
    def ok(self) -> bool:
        return self.status in ("ok", "cut")


@dataclass(frozen=True)
class RunSettings:
    """What every run of a sweep shares."""

    script: str  # absolute path
    label: str  # the script as the user named it: error messages show this
    scene: str  # a bundled name or an absolute path
    seconds: float | None = None  # cut each run after this much simulated time
    timeout: float = 300.0  # wall-clock limit per run (and script clock without ``seconds``)
    after: float = 0.0
    server: str | None = None
    cwd: str = ""  # where the scripts run (the sweep's directory), so relative files resolve

    def job(self, run: RunSpec) -> dict[str, Any]:
        """A run as a plain dict, for a worker's pipe or a Ray task."""
        return {**asdict(self), "index": run.index, "seed": run.seed, "args": list(run.args)}


class FinalState:
    """``probe`` for run_script: the robot's pose and the joints at the last pass; with
    ``seconds``, it ends the script once that much simulated time has passed (summed over the
    run's simulations), as the clock's own limit would (ScriptTimeout, counted simulated)."""

    def __init__(self, seconds: float | None = None) -> None:
        self.seconds = seconds
        self.state: dict[str, Any] = {}  # the same dict every pass: it survives a raise
        self._joints: tuple[Any, tuple[str, ...]] | None = None

    def __call__(self, sim: Any) -> dict[str, Any]:
        world = sim.world
        if world is None:
            return self.state
        try:
            self._capture(world)
        except Exception:  # noqa: BLE001 (a scene without a robot: no pose, the run goes on)
            pass
        if self.seconds is not None and sim.passes * sim.pass_dt >= self.seconds - 1e-9:
            from sims.remote_api.clock import ScriptTimeout

            self.state["cut"] = True
            sim.clock.timed_out = True
            raise ScriptTimeout(f"cut at {self.seconds:g} simulated seconds")
        return self.state

    def _capture(self, world: Any) -> None:
        from sims.quiet import pybullet as p

        model = world.model
        if self._joints is None or self._joints[0] is not model:
            self._joints = (model, tuple(j.name for j in model.joints))
        (x, y, z), orn = world.object_pose(model.robot)
        m = p.getMatrixFromQuaternion(orn)
        ax = model.forward_axis
        heading = math.atan2(
            m[3] * ax[0] + m[4] * ax[1] + m[5] * ax[2], m[0] * ax[0] + m[1] * ax[1] + m[2] * ax[2]
        )
        self.state.update(
            robot=model.robot,
            x=x,
            y=y,
            z=z,
            heading=heading,
            quaternion=list(orn),
            joints={name: world.joint_position(name) for name in self._joints[1]},
        )


def parse_value(text: str) -> Any:
    if len(text) >= 2 and text[0] == text[-1] == '"':
        return text[1:-1]
    try:
        value = json.loads(text)
    except ValueError:
        return text
    if isinstance(value, float) and not math.isfinite(value):
        return text
    return value if isinstance(value, (int, float, bool)) or value is None else text


def parse_results(output: str) -> dict[str, Any]:
    """``RESULT key=value key2="a b"`` lines; a later value of a key replaces an earlier one."""
    found: dict[str, Any] = {}
    for line in output.splitlines():
        m = RESULT_LINE.match(line.strip())
        if m:
            for key, value in RESULT_PAIR.findall(m.group(1)):
                found[key] = parse_value(value)
    return found


def read_result_file(path: Path) -> tuple[dict[str, Any], str]:
    """The JSON object the script wrote (empty when it wrote none) and a problem, if any."""
    if not path.is_file():
        return {}, ""
    try:
        if path.stat().st_size > MAX_RESULT_FILE:
            return {}, f"{RESULT_FILE_ENV}: larger than {MAX_RESULT_FILE} bytes: ignored"
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        return {}, f"{RESULT_FILE_ENV}: not JSON: {exc}"
    if not isinstance(data, dict):
        return {}, f"{RESULT_FILE_ENV}: holds a {type(data).__name__}, not a JSON object"
    return {str(k): v for k, v in data.items()}, ""


@contextlib.contextmanager
def _environment(env: dict[str, str], cwd: str):
    """The run's variables and folder, in this (worker) process while the child is forked."""
    saved = {k: os.environ.get(k) for k in env}
    here = os.getcwd()
    os.environ.update(env)
    try:
        if cwd and os.path.isdir(cwd):
            os.chdir(cwd)
        yield
    finally:
        os.chdir(here)
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


@contextlib.contextmanager
def _no_stdin():
    """``input()`` in a run reads an empty stream (EOF), as with `remote-api run` without
    ``--stdin``; never the worker's own job channel."""
    saved, sys.stdin = sys.stdin, io.StringIO("")
    try:
        yield
    finally:
        sys.stdin = saved


_warm: set[str | None] = set()


def warm(scene: str | None) -> None:
    """Import what a run needs and load the scene once, in this process, before runs fork
    from it (each run would otherwise import and decode it again in its child)."""
    if scene in _warm:
        return
    _warm.add(scene)
    import sims.remote_api.api  # noqa: F401 (the legacy `sim` module's body)
    import sims.remote_api.runner  # noqa: F401
    import sims.remote_api.zmq.client  # noqa: F401
    from sims.quiet import pybullet  # noqa: F401

    if scene is not None:
        with contextlib.suppress(Exception):  # a bad scene is reported by the run itself
            from sims.world import World

            World(scene).close()  # builders' caches filled once, not per run
    import gc

    gc.collect()
    gc.freeze()  # a forked run's collections then leave the worker's pages alone (no copies)


def execute(job: dict[str, Any]) -> dict[str, Any]:
    """Run one job (:meth:`RunSettings.job`) and return its record as a dict."""
    from sims.remote_api.runner import run_script

    warm(job["scene"])
    run = RunSpec(job["index"], job["seed"], tuple(tuple(a) for a in job["args"]))
    seconds, timeout = job["seconds"], job["timeout"]
    started = time.monotonic()
    out, err = io.StringIO(), io.StringIO()
    with tempfile.TemporaryDirectory(prefix="sitegen-run-") as tmp:
        result_file = Path(tmp) / "result.json"
        env = {**run.env(), RESULT_FILE_ENV: str(result_file)}
        with (
            _environment(env, job["cwd"]),
            contextlib.redirect_stdout(out),
            contextlib.redirect_stderr(err),
            _no_stdin(),
        ):
            try:
                result = run_script(
                    job["script"],
                    job["scene"],
                    seed=run.seed,
                    server=job["server"],
                    after=job["after"],
                    timeout=timeout,
                    wall_timeout=timeout,
                    argv=run.argv(),
                    stderr=err,
                    trace=False,
                    probe=FinalState(seconds),
                )
            except Exception as exc:  # the runner's own failure: this run's record says so
                result = None
                failure = f"{job['label']}: the runner failed: {type(exc).__name__}: {exc}"
        from_file, problem = read_result_file(result_file)
    record = RunRecord(run.index, run.seed, dict(run.args), "failed", 1)
    record.wall_seconds = round(time.monotonic() - started, 3)
    record.host = f"{os.uname().nodename}:{os.getpid()}"
    if result is None:
        record.error = failure
        record.log = _tail(out.getvalue() + err.getvalue())
        return record.to_json()
    record.exit_code = result.exit_code
    record.sim_seconds = round(result.sim_time, 6)
    record.simulations = result.simulations
    record.results = {**parse_results(out.getvalue()), **from_file}
    record.final = dict(result.probe or {})
    cut = bool(record.final.pop("cut", False))
    message = (result.message or "").replace(job["script"], job["label"])
    if result.exit_code == 0 or cut:
        record.status = "cut" if cut and result.exit_code != 0 else "ok"
    else:
        record.status = "timeout" if result.timed_out else "failed"
        record.error = message or f"{job['label']}: exit {result.exit_code}"
        record.log = _tail(out.getvalue() + err.getvalue())
    if problem:
        record.error = "; ".join(x for x in (record.error, problem) if x)
    return record.to_json()


def lost_record(job: dict[str, Any], error: str, status: str, attempts: int) -> dict[str, Any]:
    """The record of a run that gave no record of its own (its worker was lost or killed)."""
    record = RunRecord(job["index"], job["seed"], dict(tuple(a) for a in job["args"]), status, -1)
    record.error = f"{job['label']}: run {job['index']}: {error}"
    record.attempts = attempts
    return record.to_json()


def _tail(text: str) -> str:
    return text[-LOG_TAIL:]
