"""Sweep throughput: runs per second one after another in one process, and as a sweep on 1 and
2 local workers and on a Ray cluster of two nodes started with ``ray start`` on this machine.

    python bench/sweep_bench.py [--runs 60] [--seconds S] [--script PATH] [--no-ray]

Prints each figure, the sweep's overhead per run over the one-process loop (the issue's limit:
10%) and the scaling efficiency (speed-up over one worker / workers). The one-process loop runs
the same runs through ``run_script(isolate=False)`` with the same final-state probe, so the
difference is what a sweep adds: a worker process, a forked isolated child per run, the pipes.
Every configuration's results.csv is checked to be byte-identical to the one-worker sweep's.
Say how loaded the machine was (``uptime``) with the figures: on a shared machine they vary.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_name] = "1"  # as in the sweep's workers (sims/sweeps/worker.py): same baseline

from sims import runs  # noqa: E402
from sims.sweeps.one_run import FinalState, warm  # noqa: E402
from sims.sweeps.plan import plan_runs  # noqa: E402


def one_process(settings, planned, isolate: bool = False) -> tuple[float, float]:
    """The same runs, one after another, in this process: (wall s, CPU s). ``isolate=False``:
    no fork at all; True: each run isolated by run_script as `remote-api run` isolates it (a
    user's own loop over run_script)."""
    from sims.remote_api.runner import run_script

    warm(settings.scene)
    start, cpu = time.monotonic(), _own_cpu()
    for run in planned:
        sink = io.StringIO()
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            result = run_script(
                settings.script,
                settings.scene,
                seed=run.seed,
                timeout=settings.timeout,
                argv=run.argv(),
                trace=False,
                probe=FinalState(settings.seconds),
                isolate=isolate,
                stderr=sink,
            )
        assert result.exit_code in (0, 124), result.message
    return time.monotonic() - start, _own_cpu() - cpu


def _own_cpu() -> float:
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def _tree_cpu(pids: list[int]) -> float:
    """CPU seconds of these processes and of their children they reaped (the forked runs)."""
    total = 0
    for pid in pids:
        stat = Path(f"/proc/{pid}/stat").read_bytes()
        fields = stat[stat.rfind(b")") + 2 :].split()
        total += sum(int(x) for x in fields[11:15])  # utime stime cutime cstime
    return total / os.sysconf("SC_CLK_TCK")


def timed_sweep(settings, planned, out: Path, executor) -> tuple[float, bytes]:
    start = time.monotonic()
    outcome = runs.sweep(settings, planned, out, executor)
    assert not outcome.failed, outcome.failed[0].error
    return time.monotonic() - start, outcome.csv.read_bytes()


def local(settings, planned, out: Path, workers: int) -> tuple[float, float, bytes]:
    """(wall s, CPU s, results.csv) of the runs on ``workers`` local workers. The workers are
    started by a first small batch and kept for the timed sweep (as an optimiser keeps them
    between generations): a worker's start is once per sweep, not per run."""
    from sims.sweeps.local import LocalExecutor

    with LocalExecutor(workers) as executor:
        runs.run_all(settings, planned[:workers], executor)
        pids = [w.process.pid for w in executor._pool.workers]
        cpu = _tree_cpu(pids)
        took, csv = timed_sweep(settings, planned, out, executor)
        cpu = _tree_cpu(pids) - cpu
    return took, cpu, csv


def ray_two_nodes(settings, planned, out: Path) -> tuple[float, bytes] | None:
    try:
        import ray
    except ImportError:
        print("ray: not installed (pip install ray): skipped")
        return None
    temp = tempfile.mkdtemp(prefix="rb", dir="/tmp")
    env = dict(os.environ)  # RAY_AUTH_MODE and RAY_AUTH_TOKEN set by main()
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    cli = [str(Path(sys.executable).with_name("ray")), "start", "--node-ip-address=127.0.0.1"]
    cli += ["--num-cpus=1", "--disable-usage-stats"]
    head = [*cli, "--head", f"--port={port}", "--include-dashboard=false", f"--temp-dir={temp}"]
    try:
        for command in (head, [*cli, f"--address=127.0.0.1:{port}"]):
            subprocess.run(command, env=env, check=True, capture_output=True, timeout=300)
        ray.init(address=f"127.0.0.1:{port}", log_to_driver=False, _node_ip_address="127.0.0.1")
        runs.sweep(settings, planned[:4], out / "warm", "ray")  # workers started, code imported
        with runs.make_executor("ray") as executor:
            return timed_sweep(settings, planned, out, executor)
    finally:
        with contextlib.suppress(Exception):
            ray.shutdown()
        _end(temp)
        shutil.rmtree(temp, ignore_errors=True)


def _end(temp: str) -> None:
    """The Ray processes this bench started (their command lines name its folder) and below."""

    def title(p: int) -> str:
        try:
            return (
                Path(f"/proc/{p}/cmdline")
                .read_bytes()
                .replace(b"\0", b" ")
                .decode("utf-8", "replace")
            )
        except OSError:
            return ""

    def parent(p: int) -> int:
        try:
            stat = Path(f"/proc/{p}/stat").read_bytes()
            return int(stat[stat.rfind(b")") + 2 :].split()[1])
        except (OSError, ValueError, IndexError):
            return -1

    pids = [int(p) for p in os.listdir("/proc") if p.isdigit()]
    found = {p for p in pids if temp in title(p)}
    while more := {p for p in pids if p not in found and parent(p) in found}:
        found |= more
    for p in found - {os.getpid()}:
        with contextlib.suppress(OSError):
            os.kill(p, signal.SIGKILL)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=60)
    parser.add_argument("--rounds", type=int, default=3, help="best of (a shared machine)")
    parser.add_argument("--seconds", type=float, help="cut each run after S simulated seconds")
    parser.add_argument("--script", default=str(ROOT / "examples/sweeps/arm_random_reach.py"))
    parser.add_argument("--no-ray", action="store_true")
    args = parser.parse_args()
    # Ray reads its settings when imported: the bench's own two-node cluster's token, first
    os.environ.update(RAY_AUTH_MODE="token", RAY_AUTH_TOKEN=secrets.token_hex(32))
    settings = runs.settings_for(args.script, "2w1a", seconds=args.seconds, label="bench")
    planned = plan_runs(range(args.runs))
    n = args.runs
    print(f"{n} runs of {Path(args.script).name}, best of {args.rounds} rounds; "
          f"load average at the start {os.getloadavg()[0]:.2f}")  # fmt: skip
    best: dict[str, tuple[float, float]] = {}

    def keep(name: str, wall: float, cpu: float) -> None:
        if name not in best or wall < best[name][0]:
            best[name] = (wall, min(cpu, best.get(name, (0, cpu))[1]))

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        ref = None
        for r in range(args.rounds):
            keep("one", *one_process(settings, planned))
            keep("isolated", *one_process(settings, planned, isolate=True))
            for workers in (1, 2):
                wall, cpu, csv = local(settings, planned, out / f"l{workers}-{r}", workers)
                assert ref is None or csv == ref, f"{workers} workers gave other results"
                ref = csv
                keep(f"local{workers}", wall, cpu)
        (t0, c0), (t1, c1), (t2, _) = best["one"], best["local1"], best["local2"]
        ti, ci = best["isolated"]
        print(f"one process, one after another, not isolated: {n / t0:.2f} runs/s ({t0:.1f} s, "
              f"{c0 / n:.3f} CPU s a run)")  # fmt: skip
        print(f"one process, one after another, each isolated by run_script: {n / ti:.2f} "
              f"runs/s ({ti:.1f} s, {ci / n:.3f} CPU s a run)")  # fmt: skip
        print(f"sweep, 1 local worker: {n / t1:.2f} runs/s ({t1:.1f} s, {c1 / n:.3f} CPU s a "
              f"run); overhead per run over not isolated: wall {100 * (t1 / t0 - 1):+.1f}%, "
              f"CPU {100 * (c1 / c0 - 1):+.1f}%; over isolated: wall "
              f"{100 * (t1 / ti - 1):+.1f}%, CPU {100 * (c1 / ci - 1):+.1f}%")  # fmt: skip
        print(f"sweep, 2 local workers: {n / t2:.2f} runs/s ({t2:.1f} s); speed-up over 1 "
              f"worker {t1 / t2:.2f}x, efficiency {50 * t1 / t2:.0f}%")  # fmt: skip
        if not args.no_ray:
            got = ray_two_nodes(settings, planned, out / "ray")
            if got is not None:
                t3, csv3 = got
                assert csv3 == ref, "Ray gave other results"
                print(f"sweep, Ray 2 nodes x 1 CPU: {n / t3:.2f} runs/s ({t3:.1f} s); speed-up "
                      f"over 1 worker {t1 / t3:.2f}x, efficiency {50 * t1 / t3:.0f}%")  # fmt: skip
        print("results.csv identical across executors: yes")
        print(f"load average at the end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
