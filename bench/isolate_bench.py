"""Benchmark: what running a remote API script in its own child process costs (issue 15).

    python bench/isolate_bench.py [--runs N] [--script PATH] [--scene 2w1a|cart]

Times ``run_script`` end to end (fork, network namespace, result sent back, cleanup) against
the same run inside this process (``isolate=False``), alternating the two, and prints the
medians and the difference per run.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
DEFAULT_SCRIPT = REPO.parent / "shared" / "seeds" / "scripts" / "task2-2_cart_velocity.py"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--script", type=Path, default=DEFAULT_SCRIPT)
    parser.add_argument("--scene", default="cart")
    args = parser.parse_args(argv)
    if not args.script.is_file():
        print(f"no script at {args.script}", file=sys.stderr)
        return 2
    from sims.remote_api.runner import run_script

    times: dict[bool, list[float]] = {True: [], False: []}
    isolation = ""
    for i in range(args.runs * 2):
        isolate = i % 2 == 0
        sink = io.StringIO()
        started = time.perf_counter()
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            result = run_script(args.script, args.scene, trace=False, isolate=isolate)
        times[isolate].append(time.perf_counter() - started)
        if not result.ok:
            print(f"run {i} failed: {result.message}", file=sys.stderr)
            return 1
        isolation = result.isolation if isolate else isolation
    child, here = statistics.median(times[True]), statistics.median(times[False])
    print(f"script: {args.script.name} on {args.scene}, {args.runs} runs each")
    print(f"child process ({isolation}): median {child * 1000:.0f} ms")
    print(f"in this process:                median {here * 1000:.0f} ms")
    print(f"cost of the child: {(child - here) * 1000:+.0f} ms per run ({child / here:.2f}x)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
