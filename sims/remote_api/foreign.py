"""``sitegen remote-api run SCRIPT --python PATH``: the script runs in the user's own Python (any
version, any packages: numpy < 1.24 for the course's check-point helper) and talks to the
emulated scene over loopback sockets, as a script talks to CoppeliaSim.

The server (``serve.serving``: ZeroMQ on 23000, legacy on 19997 and 19999, and the bridge of
``rpc.py``) and the script's process both live in the run's isolated child (isolate.py), whose
network namespace has nothing but a loopback interface, brought up here: nothing the script
does reaches any other address, and CoppeliaSim's own ports are free in there. The script
starts through ``foreign_shim/bootstrap.py`` (which chooses its client modules). Time is the
wall clock (``speed`` scales it); a stepped script is deterministic, a free-running one is not.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import socket
import struct
import subprocess
import sys
import threading
from pathlib import Path
from typing import Any

from .clock import real_monotonic, real_sleep

BOOTSTRAP = Path(__file__).resolve().parent / "foreign_shim" / "bootstrap.py"
SIOCGIFFLAGS, SIOCSIFFLAGS, IFF_UP = 0x8913, 0x8914, 0x1


def bring_up_loopback() -> bool:
    """Set the ``lo`` interface up (a new network namespace starts with it down); True when it
    is up afterwards."""
    with contextlib.suppress(OSError), socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        ifreq = struct.pack("16sH14s", b"lo", 0, b"\0" * 14)
        flags = struct.unpack("16sH14s", fcntl.ioctl(s, SIOCGIFFLAGS, ifreq))[1]
        if flags & IFF_UP:
            return True
        fcntl.ioctl(s, SIOCSIFFLAGS, struct.pack("16sH14s", b"lo", flags | IFF_UP, b"\0" * 14))
        return True
    return False


def interpreter_problem(python: str) -> str | None:
    """Why ``python`` cannot run a script (None: it can)."""
    import shutil

    found = shutil.which(python) if os.sep not in python else python
    if not found or not os.path.isfile(found) or not os.access(found, os.X_OK):
        return f"--python {python}: no such interpreter"
    try:
        done = subprocess.run(
            [found, "-c", "import sys; print(sys.version_info[:2] >= (3, 8))"],
            capture_output=True,
            text=True,
            timeout=60,
        )
    except (OSError, subprocess.TimeoutExpired) as exc:
        return f"--python {python}: cannot run it: {exc}"
    if done.returncode != 0 or done.stdout.strip() != "True":
        return f"--python {python}: not a Python 3.8 or later interpreter"
    return None


class _Locked:
    """A text stream whose writes hold one lock shared by all the run's streams: the script's
    output pumps and the server's threads write from several threads, and the isolated child
    relays every stream through one pipe that must not get two messages at once."""

    def __init__(self, stream: Any, lock: threading.Lock):
        self.stream, self.lock = stream, lock

    def write(self, text: str) -> int:
        with self.lock:
            n = self.stream.write(text)
            self.stream.flush()
        return n

    def flush(self) -> None:
        with self.lock:
            self.stream.flush()

    def __getattr__(self, name: str) -> Any:
        return getattr(self.stream, name)


def _pump(stream: Any, target: Any) -> None:
    for line in iter(stream.readline, ""):
        target.write(line)


def run_foreign(
    script: str | Path,
    scene: str,
    python: str,
    *,
    seed: int | None = 0,
    server: str | None = None,
    after: float = 0.0,
    timeout: float | None = None,
    wall_timeout: float | None = None,
    argv: Any = (),
    speed: float = 1.0,
    stderr: Any = None,
    world: Any = None,
    on_pass: Any = None,
    scene_options: dict[str, Any] | None = None,
):
    """Run ``script`` in ``python`` against a server holding ``scene``; returns a RunResult."""
    from .run_result import RunResult

    label = str(script)
    path = Path(script).resolve()
    result = RunResult(label, scene, exit_code=0, isolation="own Python, over loopback")
    if not path.is_file():
        result.exit_code, result.message = 2, f"{label}: no such script file"
        return result
    problem = interpreter_problem(python)
    if problem:
        result.exit_code, result.message = 2, problem
        return result
    lock = threading.Lock()
    saved_streams = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = _Locked(sys.stdout, lock), _Locked(sys.stderr, lock)
    stderr = _Locked(stderr, lock) if stderr is not None else sys.stderr
    try:
        with contextlib.ExitStack() as stack:
            from .isolate import fenced, thread_network_namespace

            if fenced() is None:  # a run in an unfenced process (a clip's recorder): this thread,
                # the server's threads and the script's process get a namespace of their own
                if stack.enter_context(thread_network_namespace()):
                    result.isolation = "own Python, over loopback in its own network namespace"
            bring_up_loopback()
            return _run_foreign(
                script,
                scene,
                python,
                path,
                label,
                result,
                stderr,
                seed=seed,
                server=server,
                after=after,
                timeout=timeout,
                wall_timeout=wall_timeout,
                argv=argv,
                speed=speed,
                world=world,
                on_pass=on_pass,
                scene_options=scene_options,
            )
    finally:
        sys.stdout, sys.stderr = saved_streams


def _run_foreign(
    script, scene, python, path, label, result, stderr, *, seed, server, after, timeout,
    wall_timeout, argv, speed, world, on_pass, scene_options,
):  # fmt: skip
    from .serve import serving

    limit = wall_timeout if wall_timeout is not None else timeout
    started = real_monotonic()
    stopped: list[BaseException] = []
    factory = None
    if world is not None:
        factory = _guarded_world(world, stopped)
    try:
        served = serving(
            scene,
            seed=seed or 0,
            speed=speed,
            server=server,
            scene_options=scene_options,
            stderr=stderr,
            world_factory=factory,
        )
        context = served.__enter__()
    except OSError as exc:  # a port taken (outside an own network namespace)
        result.exit_code = 2
        result.message = f"{label}: cannot serve the scene on CoppeliaSim's ports: {exc}"
        return result
    session = context.session
    sim = session.simulator
    if on_pass is not None:
        sim.pass_observers.append(on_pass)
    sim.pass_observers.append(lambda s: result.samples.append(_sample(s)))
    from .rpc import Bridge

    bridge = Bridge(session).start()
    env = dict(os.environ)
    env.update(
        SITEGEN_REMOTE_API_BRIDGE=str(bridge.port),
        SITEGEN_REMOTE_API_SEED=str(seed or 0),
        PYTHONUNBUFFERED="1",
    )
    env.pop("PYTHONPATH", None)  # the user's interpreter with its own packages only
    try:
        try:
            stdin_data = sys.stdin.read() if sys.stdin is not None else ""
        except (OSError, ValueError):
            stdin_data = ""
        proc = subprocess.Popen(
            [python, str(BOOTSTRAP), str(path), *map(str, argv)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
        )
        pumps = [
            threading.Thread(target=_pump, args=(proc.stdout, sys.stdout), daemon=True),
            threading.Thread(target=_pump, args=(proc.stderr, sys.stderr), daemon=True),
        ]
        for p in pumps:
            p.start()
        with contextlib.suppress(OSError):
            proc.stdin.write(stdin_data)
            proc.stdin.close()
        code = _wait(proc, limit, stopped)
        for p in pumps:
            p.join(timeout=5.0)
        if code is None:
            result.exit_code, result.timed_out = 124, True
            result.message = (
                f"{label}: stopped: the script ran past its time limit of {limit:g} s "
                "(wall-clock time)"
            )
        elif stopped:
            result.exit_code = 0
        else:
            result.exit_code = code if code >= 0 else 128 - code
            if code != 0:
                result.message = f"{label}: the script's Python exited with status {code}"
        if after > 0 and not stopped and result.exit_code == 0:
            from .zmq.server import release_stepping

            with session.lock:
                release_stepping(session)
            real_sleep(after / speed)
    finally:
        bridge.stop()
        result.wall_time = real_monotonic() - started
        result.clock_time = session.clock.now()
        result.sim_time = sim.passes * sim.pass_dt
        result.simulations = sim.starts
        result.final_state = sim.state
        result.connections = list(session.connections)
        result.statusbar = list(sim.statusbar)
        result.missing = list(session.missing)
        if world is not None:
            session.simulator.world = None  # the caller's World: not closed here
            world.__dict__.pop("step", None)  # its own step again (see _guarded_world)
        served.__exit__(None, None, None)
    if stopped:
        raise stopped[0]  # the clip recorder ended the run: let it through
    return result


def _wait(proc: subprocess.Popen, limit: float | None, stopped: list) -> int | None:
    """The process's exit status, or None when it was killed at ``limit`` (wall s)."""
    deadline = None if limit is None else real_monotonic() + limit
    while True:
        try:
            return proc.wait(timeout=0.05)
        except subprocess.TimeoutExpired:
            pass
        if stopped or (deadline is not None and real_monotonic() > deadline):
            proc.kill()
            proc.wait()
            return None if not stopped else 0


def _guarded_world(world: Any, stopped: list):
    """The caller's World, whose steps end the run when the clip recorder says it is done."""
    real_step = world.step

    def step(*args: Any, **kwargs: Any) -> Any:
        if stopped:
            return None
        try:
            return real_step(*args, **kwargs)
        except BaseException as exc:
            if type(exc).__module__ == "sims.recording":
                stopped.append(exc)
                return None
            raise

    world.step = step
    return lambda *a, **k: world


def _sample(sim: Any):
    from .run_result import sample_of

    return sample_of(sim)
