"""Benchmark: a stepped ZeroMQ client over loopback against `remote-api serve`, on the 2W1A.

    python bench/zmq_wire_bench.py [--steps N]

Prints, measured back to back on one machine state: the bare physics rate (simulation passes
of 50 ms, ten 5 ms physics steps each, stepped directly on a World), the stepped client's rate
over loopback ZeroMQ (the official PyPI client, ``sim.step()`` per pass, simulation running),
the round-trip rate of ``sim.step()`` with the simulation stopped (the transport alone), and
what a pass costs through the wire beyond its physics.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=1000)
    args = parser.parse_args(argv)
    from coppeliasim_zmqremoteapi_client import RemoteAPIClient

    from sims.remote_api.serve import serving
    from sims.world import World

    n = args.steps
    with World("2w1a") as world:
        started = time.perf_counter()
        for _ in range(n):
            world.step(10)
        bare = n / (time.perf_counter() - started)
    with serving("2w1a", zmq_port=0, legacy_ports=(0,)) as served:
        client = RemoteAPIClient("127.0.0.1", served.zmq_port)
        sim = client.require("sim")
        sim.setStepping(True)
        sim.startSimulation()
        started = time.perf_counter()
        for _ in range(n):
            sim.step()
        stepped = n / (time.perf_counter() - started)
        sim.stopSimulation()
        started = time.perf_counter()
        for _ in range(n):
            sim.step()
        trips = n / (time.perf_counter() - started)
        del sim, client
    print(f"bare physics:            {bare:8.0f} passes/s")
    print(f"stepped over ZeroMQ:     {stepped:8.0f} steps/s ({stepped / bare:.2f}x bare physics)")
    print(f"round trips (stopped):   {trips:8.0f} calls/s")
    print(f"wire cost per step:      {1000 / stepped - 1000 / bare:8.3f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
