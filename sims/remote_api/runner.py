"""Run a course script unchanged against a pybullet scene: ``import sim`` resolves to the emulation.

``run_script`` executes the script with runpy as ``__main__`` (its directory on ``sys.path``,
after the shim directory that provides ``sim``/``vrep``/``simConst``/``vrepConst``), on a virtual
clock by default: ``time.sleep`` lets simulated time pass at once, so a script that sleeps 80 s
finishes in seconds. Python's ``random`` is seeded (``random.seed()`` without an argument in the
script reuses that seed), so a run is reproducible. The script runs in a child process that is
killed, with every process it started, when the script ends or runs out of time, and which has
no network: a network namespace of its own (isolate.py) plus a socket guard in the process
(script_fences.py, with the script's import path and wall-clock watchdog).

Outcome: a ``RunResult`` with the exit code, a one-line message for errors/time-outs naming the
script line, simulated/wall/virtual seconds, the addresses the script asked for (recorded, never
contacted) and a per-pass trace of the robot's pose.
"""

from __future__ import annotations

import contextlib
import inspect
import math
import runpy
import sys
import threading
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .client import Connection, Session, set_session
from .clock import Clock, ScriptTimeout, VirtualClock, WallClock, patch_time, real_monotonic
from .isolate import run_isolated, thread_network_namespace
from .script_fences import Watchdog, no_network, script_environment
from .zmq import uses_zmq
from .zmq.server import release_stepping

DEFAULT_TIMEOUT = 300.0


@dataclass
class Sample:
    """The robot body at the end of one simulation pass."""

    clock: float  # script clock (s)
    sim_time: float  # simulation time of the current simulation (s)
    run: int  # 1 for the first simulation, 2 after the first restart...
    x: float
    y: float
    z: float
    heading: float  # rad


@dataclass
class RunResult:
    script: str
    scene: str
    exit_code: int
    message: str | None = None
    message_printed: bool = False  # sys.exit("text") printed its text already
    timed_out: bool = False
    sim_time: float = 0.0  # simulated seconds run, over all simulations
    wall_time: float = 0.0
    clock_time: float = 0.0  # the script's clock at the end (virtual or wall)
    connections: list[Connection] = field(default_factory=list)
    statusbar: list[str] = field(default_factory=list)
    samples: list[Sample] = field(default_factory=list)
    simulations: int = 0
    final_state: str = "stopped"  # the simulation's state when the run ended
    isolation: str = "in-process"  # how the run was fenced in (see isolate.py)
    missing: list[Any] = field(default_factory=list)  # client.Missing: names/functions lacking
    probe: Any = None  # what ``probe(simulator)`` returned at the last pass (run_script)

    @property
    def ok(self) -> bool:
        return self.exit_code == 0

    def summary(self) -> str:
        speed = self.sim_time / self.wall_time if self.wall_time > 0 else float("inf")
        addresses = ", ".join(sorted({f"{c.address}:{c.port}" for c in self.connections})) or "none"
        return (
            f"{self.script}: exit {self.exit_code}; simulated {self.sim_time:.2f} s in "
            f"{self.simulations} simulation(s); script clock {self.clock_time:.2f} s; wall "
            f"{self.wall_time:.2f} s ({speed:.0f}x); connections asked for (recorded, not "
            f"contacted): {addresses}"
        ) + (f"; isolation: {self.isolation}" if self.isolation.endswith(" only") else "")


def _script_line(exc: BaseException, path: Path) -> int | None:
    if isinstance(exc, SyntaxError) and exc.filename and Path(exc.filename).resolve() == path:
        return exc.lineno
    line = None
    for frame in traceback.extract_tb(exc.__traceback__):
        if frame.filename and Path(frame.filename).resolve() == path:
            line = frame.lineno
    return line


def _where(label: str, line: int | None) -> str:
    return f"{label}:{line}" if line is not None else label


def run_script(
    script: str | Path,
    scene: str,
    *,
    seed: int | None = 0,
    server: str | None = None,
    realtime: bool = False,
    after: float = 0.0,
    timeout: float | None = DEFAULT_TIMEOUT,
    argv: Sequence[str] = (),
    world: Any = None,
    scene_options: dict[str, Any] | None = None,
    network: bool = False,
    stderr: Any = None,
    on_pass: Callable[[Any], None] | None = None,
    trace: bool = True,
    wall_timeout: float | None = None,
    isolate: bool = True,
    probe: Callable[[Any], Any] | None = None,
) -> RunResult:
    """Run ``script`` against ``scene``; see the module docstring. ``world``: drive this World
    (not closed here) instead of creating one; ``on_pass(simulator)`` runs after every pass.
    ``timeout`` limits the script's clock; ``wall_timeout`` the real time (default: the same
    number; clips pass their own wall-clock safety net, docs/clips.md).

    ``timeout`` must be a positive number of seconds (or None: no limit). With ``isolate``
    (the default) the script runs in a child process (isolate.py) that is killed, with all it
    started, when the script ends or its wall-clock limit + ``after`` + KILL_GRACE pass. A run
    that drives the caller's ``world`` or calls ``on_pass`` needs the caller's objects and runs
    in this process (the clip recorder's worker process is itself killable).

    ``probe(simulator)`` is called after every pass where the script runs (in the isolated
    child too: it is forked, so any function works, but it sees the child's memory); its
    last return value comes back as ``RunResult.probe`` (picklable). Sweeps read the final
    state of the scene through it (sims/sweeps/one_run.py)."""
    label = str(script)
    for name, value in (("timeout", timeout), ("wall_timeout", wall_timeout)):
        if value is not None and not 0 < value < math.inf:
            message = f"{label}: {name} must be a positive number of seconds, got {value:g}"
            return RunResult(label, scene, exit_code=2, message=message)
    if isolate and world is None and on_pass is None:
        # every other argument goes to the child as given (a new parameter needs no edit here)
        options = {k: v for k, v in locals().items() if k in _forwarded_parameters()}
        return _run_in_child(script, scene, options, stderr)
    path = Path(script).resolve()
    err = stderr or sys.stderr
    result = RunResult(label, scene, exit_code=0)
    if not path.is_file():
        result.exit_code, result.message = 2, f"{label}: no such script file"
        return result
    if server is None and uses_zmq(path):
        server = "continuous"  # CoppeliaSim's ZeroMQ add-on serves while stopped, like it
    clock: Clock = WallClock(timeout) if realtime else VirtualClock(timeout)
    factory = (lambda *a, **k: world) if world is not None else None
    session = Session(
        scene,
        seed=seed or 0,
        server=server,
        clock=clock,
        scene_options=scene_options,
        world_factory=factory,
        stderr=err,
    )
    sim = session.simulator
    if trace:
        sim.pass_observers.append(lambda s: result.samples.append(_sample(s)))
    if on_pass is not None:
        sim.pass_observers.append(on_pass)
    if probe is not None:
        sim.pass_observers.append(lambda s: setattr(result, "probe", probe(s)))
    previous = set_session(session)
    tid = threading.get_ident()
    started = real_monotonic()
    try:
        with contextlib.ExitStack() as stack:
            stack.enter_context(script_environment(path, argv, seed))
            stack.enter_context(patch_time(clock, tid))
            if not network:
                stack.enter_context(no_network(tid, every_thread=_in_child))
                if not _in_child:
                    cut = stack.enter_context(thread_network_namespace())
                    result.isolation = IN_PROCESS_NAMESPACE if cut else IN_PROCESS_GUARD
            _execute(path, label, clock, timeout, result, err, wall_timeout)
            clock.limit = None
            if after > 0 and sim.world is not None:
                release_stepping(session)  # the ZeroMQ client is gone: the world runs free
                clock.advance(after)
    finally:
        set_session(previous)
        result.wall_time = real_monotonic() - started
        result.clock_time = clock.now()
        result.sim_time = sim.passes * sim.pass_dt
        result.simulations = sim.starts
        result.final_state = sim.state
        result.connections = list(session.connections)
        result.statusbar = list(sim.statusbar)
        result.missing = list(session.missing)
        session.clients.clear()
        if world is None:
            session.close()
    return result


IN_PROCESS_NAMESPACE = "caller's process; the script's thread in its own network namespace"
IN_PROCESS_GUARD = "caller's process; sockets refused for the script's thread only"
KILL_GRACE = 15.0  # wall seconds past the time limit (and ``after``) before the child is killed
_in_child = False  # set in the child process: every thread there belongs to the script


def _forwarded_parameters() -> set[str]:
    """``run_script``'s parameters that the child's ``run_script`` call receives unchanged."""
    return set(inspect.signature(run_script).parameters) - {
        "script", "scene", "stderr", "isolate", "world", "on_pass"
    }  # fmt: skip


def _run_in_child(
    script: str | Path, scene: str, options: dict[str, Any], stderr: Any
) -> RunResult:
    """``run_script`` in a forked child (isolate.run_isolated); the result comes back whole."""
    label = str(script)
    wall = options["wall_timeout"] or options["timeout"]
    limit = None if wall is None else wall + max(0.0, options["after"]) + KILL_GRACE

    def in_child(err: Any) -> RunResult:
        global _in_child
        _in_child = True
        return run_script(script, scene, stderr=err, isolate=False, **options)

    outcome = run_isolated(in_child, limit, stderr, cut_network=not options["network"])
    if outcome.error is not None:
        raise outcome.error
    if isinstance(outcome.value, RunResult):
        result = outcome.value
    elif outcome.killed:
        result = RunResult(label, scene, exit_code=124, timed_out=True)
        result.message = (
            f"{label}: stopped: the script did not end within its time limit of {wall:g} s "
            "(wall-clock time); its process and every process it started were killed"
        )
    elif outcome.interrupted:
        result = RunResult(label, scene, exit_code=130, message=f"{label}: interrupted")
    else:
        code = outcome.status if outcome.status is not None else 1
        result = RunResult(label, scene, exit_code=code if code >= 0 else 128 - code)
        if code != 0:
            result.message = f"{label}: the script's process ended abruptly (status {code})"
    result.isolation = outcome.isolation or result.isolation
    return result


def _execute(
    path: Path,
    label: str,
    clock: Clock,
    timeout: float | None,
    result: RunResult,
    err: Any,
    wall_timeout: float | None = None,
) -> None:
    wall = timeout if wall_timeout is None else wall_timeout
    try:
        with Watchdog(wall, threading.get_ident()):
            runpy.run_path(str(path), run_name="__main__")
    except SystemExit as exc:
        code = exc.code
        if code is None:
            result.exit_code = 0
        elif isinstance(code, int):
            result.exit_code = code
        else:
            print(code, file=err, flush=True)
            result.exit_code, result.message, result.message_printed = 1, str(code), True
    except ScriptTimeout as exc:
        kind = "simulated" if clock.timed_out else "wall-clock"
        result.timed_out = True
        result.exit_code = 124
        result.message = (
            f"{_where(label, _script_line(exc, path))}: stopped: the script ran past "
            f"its time limit of {timeout if clock.timed_out else wall:g} s ({kind} time)"
        )
    except KeyboardInterrupt as exc:
        result.exit_code = 130
        result.message = f"{_where(label, _script_line(exc, path))}: interrupted"
    except BaseException as exc:  # the script's own error: one line, naming its line
        if _is_recording_stop(exc):
            raise
        text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        result.exit_code = 1
        result.message = f"{_where(label, _script_line(exc, path))}: {type(exc).__name__}" + (
            f": {text}" if text else ""
        )


def _is_recording_stop(exc: BaseException) -> bool:
    """The clip recorder ends a run with its own BaseException: let it through."""
    return type(exc).__module__ == "sims.recording"


def _sample(sim: Any) -> Sample:
    world = sim.world
    robot = world.model.robot
    (x, y, z), _ = world.object_pose(robot)
    return Sample(sim.clock.now(), world.time, sim.starts, x, y, z, world.heading(robot))
