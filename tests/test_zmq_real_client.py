"""The emulation against the real ZeroMQ client: the PyPI package
``coppeliasim-zmqremoteapi-client`` talks CBOR over ZeroMQ (loopback) to the same server the
runner's in-process client uses, and both clients see the same values, types and errors.
"""

from __future__ import annotations

import importlib.util
import io
import sys
from pathlib import Path

import pytest

from sims.remote_api.client import Session, set_session
from sims.remote_api.clock import VirtualClock

pytest.importorskip("zmq", reason="pyzmq is in the test extra")
pytest.importorskip("cbor2", reason="cbor2 is in the test extra")
if importlib.util.find_spec("coppeliasim_zmqremoteapi_client") is None:
    pytest.skip("coppeliasim-zmqremoteapi-client is in the test extra", allow_module_level=True)

SHIM = Path(__file__).resolve().parent.parent / "sims" / "remote_api" / "shim"


def _real_client_class():
    """The installed package, never the shim of the same name."""
    module = importlib.import_module("coppeliasim_zmqremoteapi_client")
    assert SHIM not in Path(module.__file__).resolve().parents, "the shim shadows the real client"
    assert module.RemoteAPIClient.__module__ == "coppeliasim_zmqremoteapi_client"
    return module.RemoteAPIClient


def exercise(client) -> list:
    """A script's worth of calls; returns everything the script would see."""
    sim = client.require("sim")
    seen: list = []
    body = sim.getObject("/2W1A")
    left = sim.getObject("/2W1A/LeftWheelJoint")
    seen += [body, left, sim.getObject("/2W1A/Nothing", {"noError": True})]
    seen += [sim.getObjectPosition(body, sim.handle_world), sim.getObjectAlias(left, 1)]
    seen += [sim.getSimulationState(), sim.setStepping(True), sim.startSimulation()]
    sim.setJointTargetVelocity(left, 3.0)
    seen.append(sim.setJointTargetVelocity(sim.getObject("/2W1A/RightWheelJoint"), 1.0))
    for _ in range(20):
        client.step()
    seen += [sim.getSimulationTime(), sim.getObjectPose(body, -1), sim.getJointPosition(left)]
    seen += [sim.getObjectsInTree(body, sim.object_joint_type, 1), sim.getInt32Signal("none")]
    sim.setStringSignal("s", "abc")
    sim.setFloatSignal("f", 0.5)
    seen += [sim.getStringSignal("s"), sim.getFloatSignal("f"), sim.getSimulationState()]
    for bad in (
        lambda: sim.getObject("/nope"),
        lambda: sim.getJointPosition(body),
        lambda: sim.getObjectPosition(4242, -1),
        lambda: sim.groupShapes([body]),
        lambda: sim.setJointTargetVelocity(left, "fast"),
    ):
        try:
            seen.append(("returned", bad()))
        except Exception as exc:
            seen.append(("raised", type(exc).__name__, str(exc)))
    seen.append(sim.stopSimulation())
    seen += [sim.getSimulationState(), sim.getSimulationTime()]
    return seen


def _run(scene: str, make_client) -> list:
    session = Session(scene, clock=VirtualClock(), stderr=io.StringIO())
    previous = set_session(session)
    try:
        return make_client(session)
    finally:
        set_session(previous)
        session.close()


def test_real_client_and_shim_see_the_same(monkeypatch):
    from sims.remote_api.zmq.client import RemoteAPIClient as Shim
    from sims.remote_api.zmq.wire import loopback_server

    Real = _real_client_class()
    monkeypatch.setitem(sys.modules["__main__"].__dict__, "require", None)

    def with_real(session):
        with loopback_server(session) as port:
            client = Real("127.0.0.1", port)
            client.socket.RCVTIMEO = 20000  # fail rather than hang if the server stops
            return exercise(client)

    real = _run("2w1a", with_real)
    shim = _run("2w1a", lambda session: exercise(Shim()))
    assert shim == real
    # and what they saw is what a script relies on
    assert isinstance(real[0], int) and real[2] == -1 and len(real[3]) == 3
    assert real[4] == "/2W1A/LeftWheelJoint" and real[5] == 0 and real[6] == 0
    assert real[9] == pytest.approx(1.0) and len(real[10]) == 7
    errors = [item for item in real if isinstance(item, tuple) and item[0] == "raised"]
    assert [e[1] for e in errors] == ["Exception"] * 5
    assert "sim.groupShapes is not emulated" in errors[3][2]
    assert real[-2:] == [0, 0.0]
