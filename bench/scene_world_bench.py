"""The course's 80 s 2W1A experiment on the bundled scene and the course's scene file, side by side.

    python bench/scene_world_bench.py [--repeat N] [--explain]

Runs ``../shared/seeds/scripts/task2_2w1a_random.py`` (3 simulations of 5 random arm moves, 5 s
each) unchanged through the legacy remote API emulation, on a virtual clock, once per scene per
repeat, alternating the scenes so all see the same machine load: ``2w1a`` (built from
sims/scene/bundled/2w1a.scene.json, derived from the course's 2w1a.ttt) and, when the course
data is there, ``2w1a.ttt`` read from the file: once with its decoding served by the scene cache
(sims/scene/scene_cache.py, a fresh temporary cache that the warm-up run fills: what every run
after the first sees) and once decoded in the run (cache
off). Prints simulated seconds, wall seconds and the speed (simulated / wall) of each, the best
of the repeats, and the ratio of each to ``2w1a``. Figures depend on the machine; compare
the ratio, measured in one run.

What the scene's self-collision costs (docs/scenes.md): its respondable masks let the arm and
hand hit the body and wheels; those self-contacts are about a sixth of its contact points and
most of its constraint-solver work. ``--explain``
adds the same scene with its robot's self-collision masked off (a diagnostic: NOT the scene's
physics) and, from one untimed run of each, the contact points at the end of each pass.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import io
import os
import resource
import tempfile
import time
from pathlib import Path

from sims.remote_api.runner import run_script
from sims.scene import scene_cache

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"
SCRIPT = SHARED / "seeds" / "scripts" / "task2_2w1a_random.py"
TTT = SHARED / "data" / "scenes" / "vrep_remoteapi_ex" / "2w1a" / "2w1a.ttt"


ISOLATE = True


def _cpu() -> float:
    """CPU seconds of this process and its finished children (the isolated script runs in
    one): steadier than wall time on a shared machine."""
    me, kids = (
        resource.getrusage(resource.RUSAGE_SELF),
        resource.getrusage(resource.RUSAGE_CHILDREN),
    )
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def one(scene: str, cache: str) -> tuple[float, float, float]:
    """One isolated run; ``cache``: the scene cache folder the child uses, or "off"."""
    os.environ[scene_cache.ENV] = cache  # the forked child inherits it
    sink = io.StringIO()
    cpu = _cpu()
    started = time.perf_counter()
    with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
        result = run_script(SCRIPT, scene, seed=2021, trace=False, stderr=sink, isolate=ISOLATE)
    wall = time.perf_counter() - started
    cpu = _cpu() - cpu
    if not result.ok:
        raise SystemExit(f"{scene}: {result.message}")
    return result.sim_time, wall, cpu


ARM = ("ShoulderMotor", "ElbowMotor", "WristMotor")
Log = list[tuple[int, dict[str, list]]]


def record(scene: str) -> Log:
    """The experiment's motor commands, pass by pass, from one untimed in-process run through
    the remote API (and which simulation each pass belongs to): what ``bare`` replays."""
    log: Log = []

    def on_pass(sim) -> None:
        log.append((sim.starts, {j: list(sim.world.motor_command(j) or ()) for j in ARM}))

    sink = io.StringIO()
    with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
        run_script(SCRIPT, scene, seed=2021, trace=False, stderr=sink, on_pass=on_pass)
    return log


def bare(scene: str, log: Log) -> tuple[float, float, float]:
    """The same scene stepped by pybullet alone through the same passes: the recorded arm
    commands set as the script set them, a rebuild where the script restarted the simulation,
    then ``stepSimulation`` in a loop (the World built first, in the time, as the API run builds
    it); no remote API, no script, no World.step work. The same
    physics as the API run (same commands, same steps), so its speed is the API run's floor."""
    from sims.quiet import pybullet as p
    from sims.world import World

    cpu, started = _cpu(), time.perf_counter()  # the scene's building counts, as in the API run
    world = World(scene, seed=2021)
    c, steps = world.client_id, world.pass_steps
    run, sent = log[0][0] if log else 0, {}
    for starts, commands in log:
        if starts != run:
            world.reset()
            run, sent = starts, {}
        for joint, command in commands.items():
            if command and command != sent.get(joint) and command[0] == "position":
                world.set_joint_target_position(joint, command[1])
                sent[joint] = command
        for _ in range(steps):
            p.stepSimulation(physicsClientId=c)
    wall, cpu = time.perf_counter() - started, _cpu() - cpu
    world.close()
    return len(log) * steps * world.timestep, wall, cpu


def without_self_collision(folder: Path) -> str:
    """The bundled 2W1A with the low byte of every respondable mask cleared: shapes of one model
    no longer collide with each other (the floor, another model, still holds the robot)."""
    from sims.scene.jsonfile import write_json
    from sims.scene.resolve import open_scene

    scene = open_scene("2w1a")
    objects = []
    for o in scene.objects:
        if o.shape is not None:
            d = o.shape.dynamics
            d = dataclasses.replace(d, respondable_mask=d.respondable_mask & 0xFF00)
            o = dataclasses.replace(o, shape=dataclasses.replace(o.shape, dynamics=d))
        objects.append(o)
    path = folder / "2w1a-no-self-collision.scene.json"
    write_json(dataclasses.replace(scene, objects=tuple(objects)), path)
    return str(path)


def contacts(scene: str) -> tuple[float, float]:
    """Mean contact points, and of those between two links of one body, at each pass's end
    (one untimed in-process run)."""
    from sims.quiet import pybullet as p

    seen = [0, 0, 0]

    def count(sim) -> None:
        points = p.getContactPoints(physicsClientId=sim.world.client_id)
        seen[0] += 1
        seen[1] += len(points)
        seen[2] += sum(1 for cp in points if cp[1] == cp[2])

    sink = io.StringIO()
    with contextlib.redirect_stdout(sink):
        run_script(SCRIPT, scene, seed=2021, trace=False, stderr=sink, on_pass=count)
    return seen[1] / max(seen[0], 1), seen[2] / max(seen[0], 1)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--explain", action="store_true", help="add the diagnostic rows")
    parser.add_argument(
        "--only",
        choices=("api", "bare"),
        help="one in-process run of the 2W1A scene through the remote API (writing its "
        "commands to --log), or stepped bare (replaying --log); to count instructions: "
        "valgrind --tool=callgrind python bench/scene_world_bench.py --only api --log F",
    )
    parser.add_argument("--log", help="the recorded commands (--only api writes, bare reads)")
    args = parser.parse_args()
    if not SCRIPT.is_file():
        print(f"skipped: {SCRIPT} is not there (the course's shared folder)")
        return 0
    if args.only:
        import json

        if args.only == "bare":
            sim, wall, cpu = bare("2w1a", json.loads(Path(args.log).read_text()))
        else:
            started, cpu0 = time.perf_counter(), _cpu()
            log: Log = []

            def on_pass(sim) -> None:
                log.append((sim.starts, {j: list(sim.world.motor_command(j) or ()) for j in ARM}))

            sink = io.StringIO()
            with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
                result = run_script(  # in process (on_pass); no wall limit: valgrind is slow
                    SCRIPT, "2w1a", seed=2021, trace=False, stderr=sink, wall_timeout=36000,
                    on_pass=on_pass,
                )  # fmt: skip
            sim, wall, cpu = result.sim_time, time.perf_counter() - started, _cpu() - cpu0
            if args.log:
                Path(args.log).write_text(json.dumps(log))
        print(f"{args.only}: {sim:.1f} simulated s, {wall:.2f} s wall, {cpu:.2f} s cpu")
        return 0
    with tempfile.TemporaryDirectory(prefix="scene-bench-") as tmp:
        return measure(args, Path(tmp))


def measure(args: argparse.Namespace, tmp: Path) -> int:
    cache = str(tmp / "scene-cache")
    runs = [("2w1a", "2w1a", cache)]
    if TTT.is_file():
        runs += [
            ("2w1a.ttt, cached decoding", str(TTT), cache),
            ("2w1a.ttt, decoded per run", str(TTT), "off"),
        ]
    if args.explain:
        runs.append(("2w1a, no self-collision *", without_self_collision(tmp), cache))
    for _, scene, where in runs:  # warm up: imports; fills the scene cache
        one(scene, where)
    log = record("2w1a")
    best: dict[str, tuple[float, float, float]] = {}
    for _ in range(args.repeat):
        for label, scene, where in [*runs, ("2w1a, bare pybullet stepping", "2w1a", "")]:
            if where:
                sim, wall, cpu = one(scene, where)
            else:
                sim, wall, cpu = bare(scene, log)
            old = best.get(label)
            best[label] = (
                sim,
                min(wall, old[1]) if old else wall,
                min(cpu, old[2]) if old else cpu,
            )
    base_wall = best["2w1a"][0] / best["2w1a"][1]
    base_cpu = best["2w1a"][0] / best["2w1a"][2]
    print(
        f"{'scene':<28} {'sim s':>6} {'wall s':>7} {'x real':>7} {'vs 2w1a':>8}"
        f" {'cpu s':>7} {'x real':>7} {'vs 2w1a':>8}"
    )
    for label, (sim, wall, cpu) in best.items():
        print(
            f"{label:<28} {sim:>6.1f} {wall:>7.2f} {sim / wall:>7.0f}"
            f" {sim / wall / base_wall:>8.2f}"
            f" {cpu:>7.2f} {sim / cpu:>7.0f} {sim / cpu / base_cpu:>8.2f}"
        )
    print("(best of --repeat runs; wall = elapsed, cpu = CPU time of the run, its child included)")
    api, floor = best["2w1a"], best["2w1a, bare pybullet stepping"]
    print(
        f"2w1a through the remote API vs bare pybullet stepping: "
        f"{(api[0] / api[1]) / (floor[0] / floor[1]):.2f} (wall), "
        f"{(api[0] / api[2]) / (floor[0] / floor[2]):.2f} (cpu)"
    )
    if args.explain:
        print("* diagnostic: the scene with its robot's self-collision masked off, not its physics")
        print(f"\n{'scene':<28} {'contact points':>15} {'of them self':>13}  (at each pass end)")
        for label, scene, _ in runs:
            if "decoded per run" not in label:
                total, own = contacts(scene)
                print(f"{label:<28} {total:>15.2f} {own:>13.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
