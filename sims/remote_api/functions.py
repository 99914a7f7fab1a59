"""Which remote API functions the emulation provides: ``python -m sims.remote_api.functions``
(also ``sitegen remote-api functions``); ``--markdown`` prints the tables of
docs/remote-api.md.

Legacy (``simx*``, every function of CoppeliaSim's last ``sim.py``): its status is one of
- ``emulated``: carried out by the legacy layer itself (functions_objects/session, extras);
- ``via sim.X``: carried out by the ``sim.*`` table (functions_scene.VIA) -- emulated when
  that table has ``sim.X``, else it answers the remote error flag;
- ``client side``: pure helpers of ``sim.py`` (packing, buffers);
- ``not supported``: answers ``simx_return_local_error_flag`` (custom UIs and dialogs,
  removed from CoppeliaSim 4; file transfer, refused: a script writes no server file).
Each also says whether the legacy server (``remote-api serve``) answers its command code.

ZeroMQ (``sim.*``): every function of the one table (zmq/functions.py), and the functions
CoppeliaSim's own examples and the course's scripts call, with whether each is emulated.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass

import sims.quiet  # noqa: F401  (pybullet's banner silenced before the API modules load it)

#: sim.* functions CoppeliaSim's ZeroMQ examples (CoppeliaRobotics/zmqRemoteApi clients/python)
#: and the course's ZeroMQ scripts call, read from those scripts.
EXAMPLE_CALLS = (
    "addLog getJointPosition getObject getObjectPose getSimulationState getSimulationTime "
    "getStringParam getVisionSensorImg loadScene moveToConfig moveToPose removeObject "
    "rotateAroundAxis setJointTargetForce setJointTargetVelocity setObjectPosition "
    "setStepping setVisionSensorImg startSimulation step stopSimulation createDummy "
    "callScriptFunction setJointTargetPosition getObjectPosition getObjectOrientation "
    "setObjectOrientation getObjectHandle readProximitySensor handleVisionSensor"
).split()

CLIENT_SIDE = (
    "simxPackInts simxUnpackInts simxPackFloats simxUnpackFloats simxCreateBuffer "
    "simxReleaseBuffer simxGetConnectionId simxGetLastCmdTime simxGetOutMessageInfo "
    "simxGetInMessageInfo simxPauseCommunication simxStart simxFinish simxGetPingTime simxQuery"
).split()


@dataclass(frozen=True)
class Row:
    name: str
    status: str
    wire: bool  # answered by the legacy server on the wire (legacy functions only)


def legacy_rows() -> list[Row]:
    from . import api, extras, functions_scene, legacy_commands
    from .zmq.functions import load

    table = load()
    names = sorted(n for n in api.__all__ if n.startswith("simx") and not n.startswith("simx_"))
    served = set(legacy_commands.SERVED) | set(CLIENT_SIDE)
    aliases = {alias: name for alias, name in api.ALIASES.items()}
    rows = []
    for name in names:
        base = aliases.get(name, name)
        if base in extras.UNSUPPORTED:
            status = "not supported"
        elif base in functions_scene.VIA:
            via = functions_scene.VIA[base]
            status = f"via {via}" + ("" if via in table else " (not emulated yet)")
        elif name in CLIENT_SIDE:
            status = "client side"
        else:
            status = "emulated"
        if base != name:
            status += f" (= {base})"
        rows.append(Row(name, status, base in served or name in served))
    return rows


def zmq_rows() -> list[Row]:
    from .zmq.functions import NOT_EMULATED, load

    table = load()
    names = sorted(set(table) | {f"sim.{n}" for n in EXAMPLE_CALLS})
    rows = []
    for name in names:
        if name in table:
            status = "emulated"
        elif name in NOT_EMULATED:
            status = "not emulated (error naming it)"
        else:
            status = "not emulated"
        if name[len("sim.") :] in EXAMPLE_CALLS:
            status += "; called by CoppeliaSim's examples or the course"
        rows.append(Row(name, status, True))
    return rows


def _print_text(out) -> None:
    legacy = legacy_rows()
    print(f"legacy remote API ({len(legacy)} simx functions):", file=out)
    for row in legacy:
        wire = "" if row.wire else "  [not on the wire]"
        print(f"  {row.name:34} {row.status}{wire}", file=out)
    zmq = zmq_rows()
    print(f"ZeroMQ remote API ({len(zmq)} sim.* functions):", file=out)
    for row in zmq:
        print(f"  {row.name:34} {row.status}", file=out)


def _print_markdown(out) -> None:
    print("| legacy function | status | on the wire |", file=out)
    print("|---|---|---|", file=out)
    for row in legacy_rows():
        print(f"| `{row.name}` | {row.status} | {'yes' if row.wire else 'no'} |", file=out)
    print(file=out)
    print("| ZeroMQ function | status |", file=out)
    print("|---|---|", file=out)
    for row in zmq_rows():
        print(f"| `{row.name}` | {row.status} |", file=out)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m sims.remote_api.functions",
        description="List the legacy (simx*) and ZeroMQ (sim.*) functions the emulation provides.",
    )
    parser.add_argument("--markdown", action="store_true", help="print Markdown tables")
    args = parser.parse_args(argv)
    (_print_markdown if args.markdown else _print_text)(sys.stdout)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
