"""What a threaded script costs per pass against the same logic in ``sysCall_actuation``.

    python bench/lua_thread_bench.py [--passes 2000] [--repeat 5]

Runs the project's demo scene (tools/lua_demo.py) with one child script on the arm, in two
forms doing the same work each pass (read the joint, command its velocity, read the time):
a non-threaded ``sysCall_actuation`` and a threaded ``sysCall_threadmain`` loop that calls
``sim.switchThread()`` (the coroutine resumed once per pass). Prints the CPU time per pass of
the scripts alone (the run minus the same run without a script), best of ``--repeat``.
"""

from __future__ import annotations

import argparse
import dataclasses
import gc
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from sims.lua.host import ScriptHost  # noqa: E402
from sims.scene.model import Script  # noqa: E402
from sims.world import World  # noqa: E402
from tools.lua_demo import demo_scene  # noqa: E402

WORK = (
    "local q = sim.getJointPosition(j)\n"
    "sim.setJointTargetVelocity(j, 0.5 * math.sin(sim.getSimulationTime()) - 0.1 * q)\n"
)
ACTUATION = (
    "function sysCall_init() j = sim.getObject('/Post/ArmJoint') end\n"
    "function sysCall_actuation()\n" + WORK + "end\n"
)
THREADED = (
    "function sysCall_threadmain()\n  j = sim.getObject('/Post/ArmJoint')\n"
    "  while true do\n" + WORK + "    sim.switchThread()\n  end\nend\n"
)


def run(text: str | None, threaded: bool, passes: int) -> float:
    scripts = () if text is None else (Script("child", text, 4, threaded),)
    world = World(dataclasses.replace(demo_scene(), scripts=scripts))
    host = ScriptHost(world)
    host.start()
    gc.collect()
    start = time.process_time()
    world.step(passes * host.steps_per_pass)
    spent = time.process_time() - start
    assert not host.errors, host.errors
    host.close()
    world.close()
    return spent


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--passes", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    best = {"none": 1e9, "actuation": 1e9, "threaded": 1e9}
    for _ in range(args.repeat):  # interleaved: the same machine load for each form
        best["none"] = min(best["none"], run(None, False, args.passes))
        best["actuation"] = min(best["actuation"], run(ACTUATION, False, args.passes))
        best["threaded"] = min(best["threaded"], run(THREADED, True, args.passes))
    for form in ("actuation", "threaded"):
        per = (best[form] - best["none"]) / args.passes * 1e6
        print(f"{form:10s} {per:7.1f} us of CPU per pass (scripts alone)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
