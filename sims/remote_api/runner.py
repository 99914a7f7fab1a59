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
import runpy
import sys
import threading
import traceback
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from sims.lua.keys import KeysEnded

from .client import Session, set_session
from .clock import Clock, ScriptTimeout, VirtualClock, WallClock, patch_time, real_monotonic
from .isolate import fenced, run_isolated, thread_network_namespace
from .run_result import RunResult, sample_of
from .script_fences import Watchdog, no_network, script_environment
from .shim_finder import substitute_clients
from .zmq import uses_zmq
from .zmq.server import release_stepping

DEFAULT_TIMEOUT = 300.0
MAX_TIMEOUT = 7 * 86400.0  # longer limits overflow the clocks they are waited on with


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
    python: str | None = None,
    speed: float = 1.0,
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

    ``python``: run the script in that interpreter against a served scene, over loopback
    sockets on the wall clock (``speed`` scales it); see foreign.py.

    ``probe(simulator)`` is called after every pass where the script runs (in the isolated
    child too: it is forked, so any function works, but it sees the child's memory); its
    last return value comes back as ``RunResult.probe`` (picklable). Sweeps read the final
    state of the scene through it (sims/sweeps/one_run.py)."""
    label = str(script)
    for name, value in (("timeout", timeout), ("wall_timeout", wall_timeout)):
        if value is not None and not 0 < value <= MAX_TIMEOUT:
            message = (
                f"{label}: {name} must be a positive number of seconds, at most "
                f"{MAX_TIMEOUT:g} (a week), got {value:g}"
            )
            return RunResult(label, scene, exit_code=2, message=message)
    if isolate and world is None and on_pass is None:
        # every other argument goes to the child as given (a new parameter needs no edit here)
        options = {k: v for k, v in locals().items() if k in _forwarded_parameters()}
        return _run_in_child(script, scene, options, stderr)
    if python:  # the script in its own Python, over loopback sockets (foreign.py)
        from .foreign import run_foreign

        return run_foreign(
            script,
            scene,
            python,
            seed=seed,
            server=server,
            after=after,
            timeout=timeout,
            wall_timeout=wall_timeout,
            argv=argv,
            speed=speed,
            stderr=stderr,
            world=world,
            on_pass=on_pass,
            scene_options=scene_options,
        )
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
        sim.pass_observers.append(lambda s: result.samples.append(sample_of(s)))
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
            stack.enter_context(substitute_clients())
            stack.enter_context(patch_time(clock, tid))
            if not network:
                stack.enter_context(no_network(tid, every_thread=_in_child))
                if not _in_child:
                    cut = stack.enter_context(thread_network_namespace())
                    fence = fenced()  # a clip's simulation runs in a fenced child
                    result.isolation = fence or (IN_PROCESS_NAMESPACE if cut else IN_PROCESS_GUARD)
            _execute(path, label, clock, timeout, result, err, wall_timeout)
            _check_scene_fits(session, result)
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
    if result.isolation.startswith("own Python") and outcome.isolation:
        result.isolation = f"{result.isolation}; {outcome.isolation}"
    else:
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
    except KeysEnded:  # the key file ended: the run ended as planned (sims/lua/keys.py)
        result.exit_code = 0
        result.keys_ended = True
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


WRONG_SCENE_EXIT = 3


def _check_scene_fits(session: Session, result: RunResult) -> None:
    """A script that ended well but found none of the objects it asked for ran on the wrong
    scene: that is not a success (exit 3, as --strict would give)."""
    asked = [m for m in session.missing if m.kind == "object"]
    if result.exit_code == 0 and asked and session.found_objects == 0:
        result.exit_code = WRONG_SCENE_EXIT
        names = ", ".join(repr(m.what) for m in asked[:3]) + (", ..." if len(asked) > 3 else "")
        result.message = (
            f"{result.script}: none of the {len(asked)} object(s) the script asked for is in "
            f"scene {Path(result.scene).name} ({names}): wrong --scene?"
        )


def _is_recording_stop(exc: BaseException) -> bool:
    """The clip recorder ends a run with its own BaseException: let it through."""
    return type(exc).__module__ == "sims.recording"
