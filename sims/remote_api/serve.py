"""``sitegen remote-api serve SCENE``: one scene served to real remote API clients, as a running
CoppeliaSim serves it: the ZeroMQ remote API (``zmq/wire.py``, port 23000) and the legacy remote
API (``legacy_wire.py``, port 19997 and the ports the scene's scripts start, 19999 by
default), both on 127.0.0.1 only, both answered by one ``Session``.

Time: a client that steps (``sim.setStepping(True)``, ``simxSynchronous``) moves the
simulation one pass per step, so a stepped run is deterministic; otherwise a running
simulation follows the wall clock (``speed`` scales it: 2 runs two simulated seconds per wall
second), one pass every 50 ms of clock time, on a thread of its own (``_Ticker``).
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from .client import Session, set_session
from .clock import WallClock, real_sleep

ZMQ_PORT = 23000
LEGACY_PORTS = (19997, 19999)


@dataclass
class Served:
    """A running server: its session and the ports it answers on."""

    session: Session
    zmq_port: int | None
    legacy_ports: tuple[int, ...]


class _Ticker(threading.Thread):
    """Runs the passes a free-running simulation owes the wall clock."""

    def __init__(self, session: Session):
        super().__init__(name="remote-api-ticker", daemon=True)
        self.session, self.stop_flag = session, threading.Event()

    def run(self) -> None:
        sim = self.session.simulator
        while not self.stop_flag.is_set():
            with self.session.lock:  # one pass at a time: clients get the lock in between
                sim.sync(most=1)
                wait = (sim.pass_dt - sim._debt) / sim.clock.scale
            real_sleep(min(max(wait, 0.0005), 0.05))


@contextlib.contextmanager
def serving(
    scene: str,
    *,
    seed: int = 0,
    speed: float = 1.0,
    server: str | None = None,
    zmq_port: int | None = ZMQ_PORT,
    legacy_ports: tuple[int, ...] = LEGACY_PORTS,
    scene_options: dict[str, Any] | None = None,
    stderr: Any = None,
    zmq: bool = True,
    world_factory: Any = None,
) -> Iterator[Served]:
    """Serve ``scene`` while the block runs. ``zmq_port=0`` / a legacy port 0: a free port
    the system picks (the ``Served`` record says which)."""
    from .legacy_wire import LegacyWire

    session = Session(
        scene,
        seed=seed,
        server=server,
        clock=WallClock(None, scale=speed),
        scene_options=scene_options,
        world_factory=world_factory,
        stderr=stderr,
    )
    session.simulator.served = True
    previous = set_session(session)
    ticker = _Ticker(session)
    stack = contextlib.ExitStack()
    try:
        zmq_wire = None
        if zmq:
            from .zmq.wire import ZmqWire

            zmq_wire = ZmqWire(session, zmq_port or None).start()
            stack.callback(zmq_wire.stop)
        legacy = LegacyWire(session, legacy_ports).start()
        stack.callback(legacy.stop)
        ticker.start()
        yield Served(session, zmq_wire.port if zmq_wire else None, legacy.ports)
    finally:
        ticker.stop_flag.set()
        stack.close()
        ticker.join(timeout=2.0)
        set_session(previous)
        session.close()


def serve_command(args: Any, problem: str | None, bundled: bool) -> int:
    """``sitegen remote-api serve``: serve until Ctrl+C (or ``--for`` seconds). ``problem``:
    why the scene cannot be loaded (None: it can); ``bundled``: it is a bundled name."""
    import sys
    from pathlib import Path

    if problem:
        print(f"error: {problem}", file=sys.stderr)
        return 2
    scene = args.scene if bundled else str(Path(args.scene).resolve())
    ports = tuple(args.legacy_port or LEGACY_PORTS)
    try:
        with serving(
            scene,
            seed=args.seed,
            speed=args.speed,
            server=args.server,
            zmq_port=args.zmq_port,
            legacy_ports=ports,
        ) as served:
            if args.verbosity >= 0:
                print(
                    f"[remote-api] serving {Path(scene).name} on 127.0.0.1: ZeroMQ "
                    f"{served.zmq_port}, legacy {', '.join(map(str, served.legacy_ports))} "
                    "(Ctrl+C stops)",
                    file=sys.stderr,
                    flush=True,
                )
            left = args.duration
            while left is None or left > 0:
                real_sleep(0.2 if left is None else min(0.2, left))
                left = None if left is None else left - 0.2
    except OSError as exc:
        print(f"error: cannot serve on 127.0.0.1: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        pass
    return 0
