"""The legacy remote API functions of a connection: opening and closing it, its messages and
timing, and control of the simulation (start, pause, stop, status bar, errors).

Signatures and return shapes are those of CoppeliaSim 4.2's ``sim.py``; see ``execute`` for
how operation modes and return codes behave. Scene objects, joints and sensors are in
``functions_objects``; signals, parameters and helpers are in ``extras``.
"""

from __future__ import annotations

from . import commands as cmd
from .client import current_session
from .execute import (
    INIT,
    OK,
    REMOTE,
    execute,
    flush_queued,
    int_arg,
    lookup,
    str_arg,
)


# --- connection --------------------------------------------------------------------------------
def simxStart(
    connectionAddress,
    connectionPort,
    waitUntilConnected,
    doNotReconnectOnceDisconnected,
    timeOutInMs,
    commThreadCycleInMs,
):
    """Open a connection slot (no socket is opened: the address is only recorded).

    Returns the first free client ID (0 for the first), or -1 when no scene is configured."""
    address = str_arg(connectionAddress, 1)
    port = int_arg(connectionPort, 2)
    session = current_session()
    if session is None or session.simulator is None:
        if session is not None:
            session.warn_once("no-scene", "simxStart: no scene is configured")
        else:
            import sys

            print(
                "[sim] simxStart: no scene is configured: run the script with "
                "`sitegen remote-api run SCRIPT --scene 2w1a|cart` "
                "(or set SITEGEN_REMOTE_API_SCENE)",
                file=sys.stderr,
            )
        return -1
    cid = session.connect(
        address,
        port,
        wait=bool(waitUntilConnected),
        no_reconnect=bool(doNotReconnectOnceDisconnected),
        timeout_ms=timeOutInMs,
        cycle_ms=commThreadCycleInMs,
    )
    if cid >= 0:
        session.simulator.call(blocking=True)
    return cid


def simxFinish(clientID):
    """End one connection, or every connection with -1."""
    session = current_session()
    if session is not None:
        session.finish(int_arg(clientID, 1))


def simxGetConnectionId(clientID):
    found = lookup(clientID)
    return -1 if found is None else found[1].connection_id


def simxGetPingTime(clientID):
    found = lookup(clientID)
    if found is None:
        return INIT, 0
    session, client = found
    seconds = session.simulator.call(blocking=True)
    client.last_cmd_time = session.simulator.sim_time
    return OK, int(round(seconds * 1000))


def simxGetLastCmdTime(clientID):
    """Simulation time (ms) of the last reply fetched on this connection."""
    found = lookup(clientID)
    return 0 if found is None else int(round(found[1].last_cmd_time * 1000))


def simxSynchronous(clientID, enable):
    found = lookup(clientID)
    if found is None:
        return INIT
    session, _client = found
    sim = session.simulator
    sim.call(blocking=True)
    if not sim.can_control():
        session.warn_once(
            "temporary-sync",
            "simxSynchronous: a temporary remote API server "
            "(started by a child script) has no synchronous mode (remote error)",
        )
        return REMOTE
    sim.sync()
    sim.synchronous = bool(enable)
    return OK


def simxSynchronousTrigger(clientID):
    found = lookup(clientID)
    if found is None:
        return INIT
    session, _client = found
    sim = session.simulator
    if not sim.synchronous:
        sim.call(blocking=True)
        return REMOTE
    sim.trigger()
    sim.call(blocking=True)
    _client.last_cmd_time = sim.sim_time
    return OK


def simxPauseCommunication(clientID, enable):
    found = lookup(clientID)
    if found is None:
        return INIT
    session, client = found
    with session.lock:
        if client.paused and not enable:
            session.simulator.call(blocking=False)
            flush_queued(session, client)
        client.paused = bool(enable)
    return OK


def _message_info(clientID, infoType, outgoing: bool):
    found = lookup(clientID)
    if found is None:
        return -1, 0
    session, client = found
    sim = session.simulator
    info_type = int_arg(infoType, 2)
    now_ms = int(sim.clock.now() * 1000)
    values = {0: 0, 2: 2, 3: client.calls, 7: now_ms}
    if not outgoing:
        state = 0 if sim.state == "stopped" else (1 | (2 if sim.state == "paused" else 0))
        if sim.clock.realtime:
            state |= 4
        values.update({11: int(sim.sim_time * 1000), 15: 1, 17: state})
    if info_type not in values:
        return -1, 0
    return 1, values[info_type]


def simxGetInMessageInfo(clientID, infoType):
    """(1, value) or (-1, 0); ``simx_headeroffset_server_state``: bit 0 = simulation not
    stopped, bit 1 = paused, bit 2 = real-time."""
    return _message_info(clientID, infoType, outgoing=False)


def simxGetOutMessageInfo(clientID, infoType):
    return _message_info(clientID, infoType, outgoing=True)


# --- simulation ----------------------------------------------------------------------------------
def _control(clientID, operationMode, what: str):
    found = lookup(clientID)

    def run(world):
        session, _ = found
        sim = session.simulator
        if not sim.can_control():
            session.warn_once(
                "temporary-control",
                f"simx{what.capitalize()}Simulation: this "
                "scene's remote API server is a temporary one (started by a child "
                "script): it cannot start, pause or stop simulations (remote error). "
                "Run with --server continuous to allow it.",
            )
            raise cmd.CommandError(f"a temporary server cannot {what} the simulation")
        getattr(sim, what)()
        return ()

    return execute(clientID, operationMode, ("simulation", what), run, (), setter=True)[0]


def simxStartSimulation(clientID, operationMode):
    return _control(clientID, operationMode, "start")


def simxPauseSimulation(clientID, operationMode):
    return _control(clientID, operationMode, "pause")


def simxStopSimulation(clientID, operationMode):
    """Stop the simulation; the scene returns to its initial state (as CoppeliaSim restores it)."""
    return _control(clientID, operationMode, "stop")


def simxAddStatusbarMessage(clientID, message, operationMode):
    text = str_arg(message, 2)
    found = lookup(clientID)

    def run(world):
        session = found[0]
        session.simulator.statusbar.append(text)
        session.status(text)
        return ()

    return execute(clientID, operationMode, ("statusbar",), run, (), setter=True)[0]


def simxGetLastErrors(clientID, operationMode):
    found = lookup(clientID)

    def run(world):
        errors = list(found[0].simulator.errors)
        found[0].simulator.errors.clear()
        return (errors,)

    code, out = execute(clientID, operationMode, ("errors",), run, ([],))
    return code, out[0]
