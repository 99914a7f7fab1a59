"""`sitegen remote-api serve`: real clients over loopback sockets.

- the legacy remote API: CoppeliaSim's own client library (extApi, as compiled in a PyPI
  wheel) through ctypes, against ``legacy_wire``, compared with the in-process emulation;
- the ZeroMQ remote API: the official PyPI client in a separate virtual environment, against
  the ``serve`` command, compared with the in-process run of the same stepped script;
- bad clients: malformed frames, unknown commands, huge payloads; the server goes on.
"""

from __future__ import annotations

import ctypes as ct
import math
import socket
import struct
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest
from foreign_envs import cache_dir, extapi_library, python_env

from sims.remote_api import api
from sims.remote_api import legacy_codec as codec
from sims.remote_api.client import Session, set_session
from sims.remote_api.clock import VirtualClock
from sims.remote_api.runner import run_script
from sims.remote_api.serve import serving

REPO = Path(__file__).resolve().parents[1]
B, STREAM, BUF = api.simx_opmode_blocking, api.simx_opmode_streaming, api.simx_opmode_buffer


@pytest.fixture(scope="module")
def cache() -> Path:
    return cache_dir()


class CSim:
    """The legacy client library through ctypes, with sim.py's Python call shapes."""

    def __init__(self, path: Path):
        lib = self.lib = ct.CDLL(str(path))
        i, f, p = ct.c_int32, ct.c_float, ct.POINTER
        lib.simxStart.argtypes = [ct.c_char_p, i, ct.c_ubyte, ct.c_ubyte, i, i]
        lib.simxGetObjectHandle.argtypes = [i, ct.c_char_p, p(i), i]
        lib.simxGetJointPosition.argtypes = [i, i, p(f), i]
        lib.simxSetJointTargetPosition.argtypes = [i, i, f, i]
        lib.simxGetObjectPosition.argtypes = [i, i, i, p(f), i]
        lib.simxSetStringSignal.argtypes = [i, ct.c_char_p, ct.c_char_p, i, i]
        lib.simxGetStringSignal.argtypes = [i, ct.c_char_p, p(p(ct.c_ubyte)), p(i), i]
        lib.simxGetObjects.argtypes = [i, i, p(i), p(p(i)), i]
        lib.simxGetPingTime.argtypes = [i, p(i)]

    def simxStart(self, address, port, *rest):
        return self.lib.simxStart(address.encode(), port, *rest)

    def simxGetObjectHandle(self, cid, name, mode):
        h = ct.c_int32()
        return self.lib.simxGetObjectHandle(cid, name.encode(), ct.byref(h), mode), h.value

    def simxGetJointPosition(self, cid, h, mode):
        v = ct.c_float()
        return self.lib.simxGetJointPosition(cid, h, ct.byref(v), mode), v.value

    def simxGetObjectPosition(self, cid, h, rel, mode):
        v = (ct.c_float * 3)()
        return self.lib.simxGetObjectPosition(cid, h, rel, v, mode), list(v)

    def simxSetStringSignal(self, cid, name, value, mode):
        return self.lib.simxSetStringSignal(cid, name.encode(), value, len(value), mode)

    def simxGetStringSignal(self, cid, name, mode):
        data, n = ct.POINTER(ct.c_ubyte)(), ct.c_int32()
        rc = self.lib.simxGetStringSignal(cid, name.encode(), ct.byref(data), ct.byref(n), mode)
        return rc, bytearray(data[: n.value]) if rc == 0 else bytearray()

    def simxGetObjects(self, cid, kind, mode):
        n, handles = ct.c_int32(), ct.POINTER(ct.c_int32)()
        rc = self.lib.simxGetObjects(cid, kind, ct.byref(n), ct.byref(handles), mode)
        return rc, [handles[k] for k in range(n.value)] if rc == 0 else []

    def simxGetPingTime(self, cid):
        ms = ct.c_int32()
        return self.lib.simxGetPingTime(cid, ct.byref(ms)), ms.value

    def __getattr__(self, name):  # simxSynchronous, simxStartSimulation, simxFinish...
        return getattr(self.lib, name)


def legacy_sequence(sim, port: int) -> list:
    """One stepped session of calls; what a script would see."""
    seen: list = []
    cid = sim.simxStart("127.0.0.1", port, True, True, 5000, 5)
    seen.append(("cid", cid))
    code, shoulder = sim.simxGetObjectHandle(cid, "ShoulderMotor", B)
    seen.append(("handle", code, shoulder > 0))
    seen.append(("unknown", sim.simxGetObjectHandle(cid, "NoSuchObject", B)[0]))
    code, objects = sim.simxGetObjects(cid, api.sim_handle_all, B)
    seen.append(("objects", code, len(objects)))
    seen.append(("sync", sim.simxSynchronous(cid, True)))
    seen.append(("start", sim.simxStartSimulation(cid, B)))
    seen.append(("target", sim.simxSetJointTargetPosition(cid, shoulder, 2.0, B)))
    seen.append(("stream", sim.simxGetJointPosition(cid, shoulder, STREAM)[0]))
    for _ in range(40):
        sim.simxSynchronousTrigger(cid)
    sim.simxGetPingTime(cid)
    seen.append(("buffer", sim.simxGetJointPosition(cid, shoulder, BUF)))
    seen.append(("position", sim.simxGetObjectPosition(cid, shoulder, -1, B)))
    seen.append(("signal", sim.simxSetStringSignal(cid, "hello", b"world\0!", B)))
    seen.append(("signal back", sim.simxGetStringSignal(cid, "hello", B)))
    seen.append(("stop", sim.simxStopSimulation(cid, B)))
    sim.simxFinish(cid)
    return seen


def test_coppeliasim_client_library_against_the_legacy_server(cache):
    library = extapi_library(cache)
    with serving("2w1a", zmq=False, legacy_ports=(0,)) as served:
        wire = legacy_sequence(CSim(library), served.legacy_ports[0])
    session = Session("2w1a", clock=VirtualClock())
    previous = set_session(session)
    try:
        here = legacy_sequence(api, 19997)
    finally:
        set_session(previous)
        session.close()
    assert wire == here
    seen = {k[0]: k[1:] for k in wire}
    code, angle = seen["buffer"][0]
    assert code == 0 and abs(angle - 2.0) < 0.01  # the stream followed the shoulder there
    assert seen["unknown"] == (8,) and seen["signal back"] == ((0, bytearray(b"world\0!")),)


def _closed(sock: socket.socket) -> bool:
    try:
        return sock.recv(100) == b""
    except ConnectionResetError:  # closed with our bytes unread
        return True


def _listening_addresses(port: int) -> set[str]:
    """The local addresses a TCP port listens on (from /proc/net/tcp)."""
    found = set()
    for line in Path("/proc/net/tcp").read_text().splitlines()[1:]:
        local, state = line.split()[1], line.split()[3]
        address, hex_port = local.split(":")
        if int(hex_port, 16) == port and state == "0A":  # LISTEN
            found.add(socket.inet_ntoa(struct.pack("<I", int(address, 16))))
    return found


def _message(*commands: bytes, message_id: int = 1) -> bytes:
    return codec.packets(codec.message_bytes(codec.Header(message_id, 0), list(commands), 0, 0))


def _command(code: int, mode: int, ident: bytes, pure: bytes = b"") -> bytes:
    size = codec.SUBHEADER + len(ident) + len(pure)
    sub = struct.pack("<iiHiiHiBB", size, size, len(ident), 0, code + mode, 0, 0, 0, 0)
    return sub + ident + pure


def _reply(sock: socket.socket) -> tuple[codec.Header, list[codec.Command]]:
    from sims.remote_api.legacy_wire import read_message

    return codec.parse_message(read_message(sock))


def test_legacy_server_survives_bad_clients():
    with serving("2w1a", zmq=False, legacy_ports=(0,)) as served:
        port = served.legacy_ports[0]
        assert _listening_addresses(port) == {"127.0.0.1"}
        for bad in (
            b"\x02\x00" + b"garbage",  # not a little-endian packet header
            struct.pack("<hhh", 1, 30000, 0),  # a packet larger than the client's limit
            struct.pack("<hhh", 1, 10, 0) + b"0123456789",  # shorter than a message header
        ):
            with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
                s.sendall(bad)
                assert _closed(s)  # that connection only
        with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
            unknown = _command(0x3ABC, B, b"x\0")  # a command code that does not exist
            lookup = _command(0x3001, B, b"ShoulderMotor\0")  # simxGetObjectHandle
            s.sendall(_message(unknown, lookup, message_id=7))
            header, replies = _reply(s)
            assert header.message_id == 7 and len(replies) == 2
            assert replies[0].options & 1  # the error bit
            assert not replies[1].options & 1 and struct.unpack("<i", replies[1].pure)[0] > 0


ZMQ_SCRIPT = """\
import json, math, sys
from coppeliasim_zmqremoteapi_client import RemoteAPIClient
client = RemoteAPIClient('localhost', int(sys.argv[1]) if len(sys.argv) > 1 else 23000)
sim = client.require('sim')
joints = [sim.getObject('/' + n) for n in ('ShoulderMotor', 'ElbowMotor', 'WristMotor')]
sim.setStepping(True)
sim.startSimulation()
seen = []
for k, target in enumerate((200, 100, 250)):
    sim.setJointTargetPosition(joints[k], math.radians(target))
    for _ in range(30):
        sim.step()
    seen.append([sim.getJointPosition(j) for j in joints])
sim.stopSimulation()
print(json.dumps(seen))
"""


def _angles(text: str) -> list:
    import json

    return json.loads(text.strip().splitlines()[-1])


def test_official_zmq_client_in_its_own_environment_drives_serve(cache, tmp_path, capsys):
    python = python_env(cache, "zmq-client", ["coppeliasim-zmqremoteapi-client>=2.0"])
    script = tmp_path / "stepped.py"
    script.write_text(ZMQ_SCRIPT, encoding="utf-8")
    result = run_script(script, "2w1a")
    assert result.exit_code == 0, result.message
    in_process = _angles(capsys.readouterr().out)
    zmq_port, legacy_port = _free_port(), _free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "sims.remote_api", "serve", "2w1a", "--zmq-port", str(zmq_port),
         "--legacy-port", str(legacy_port), "--for", "120"],
        cwd=REPO, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert "serving" in server.stderr.readline()
        done = subprocess.run(
            [str(python), str(script), str(zmq_port)], capture_output=True, text=True, timeout=120
        )
        assert done.returncode == 0, done.stderr
        served = _angles(done.stdout)
    finally:
        server.terminate()
        server.wait(timeout=30)
    assert served == in_process  # the same stepped run, float for float
    degrees = [[round(math.degrees(a)) for a in row] for row in served]
    assert degrees[0][0] == 200 and degrees[1][1] == 100  # shoulder, then elbow, as commanded


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_zmq_wire_bad_input_and_lockstep_clients(monkeypatch):
    zmq = pytest.importorskip("zmq")
    cbor2 = pytest.importorskip("cbor2")
    pytest.importorskip("coppeliasim_zmqremoteapi_client")
    from coppeliasim_zmqremoteapi_client import RemoteAPIClient

    from sims.remote_api.zmq import wire

    monkeypatch.setattr(wire, "MAX_REQUEST", 100_000)
    with serving("2w1a", zmq_port=0, legacy_ports=(0,)) as served:
        port = served.zmq_port
        ctx = zmq.Context()
        req = ctx.socket(zmq.REQ)
        req.setsockopt(zmq.RCVTIMEO, 5000)
        req.connect(f"tcp://127.0.0.1:{port}")
        for raw, expected in (
            (b"\xff\xfe not cbor", "not CBOR"),
            (cbor2.dumps([1, 2]), "not a map"),
            (cbor2.dumps({"args": []}), "no 'func'"),
            (cbor2.dumps({"func": "sim.noSuchFunction", "args": [], "uuid": "u"}), "does not"),
        ):
            req.send(raw)
            assert expected in cbor2.loads(req.recv())["err"]
        big = ctx.socket(zmq.REQ)
        big.setsockopt(zmq.RCVTIMEO, 1000)
        big.connect(f"tcp://127.0.0.1:{port}")
        big.send(b"x" * 200_000)  # past MAXMSGSIZE: ZeroMQ drops that peer, nothing answers
        with pytest.raises(zmq.Again):
            big.recv()
        big.close(linger=0)
        req.close(linger=0)
        ctx.term()
        # two stepping clients in two threads: the simulation steps once both asked
        clients = [RemoteAPIClient("127.0.0.1", port) for _ in range(2)]
        sims = [c.require("sim") for c in clients]
        for s in sims:
            s.setStepping(True)
        sims[0].startSimulation()
        start = sims[0].getSimulationTime()

        def steps(s):
            for _ in range(10):
                s.step()

        threads = [threading.Thread(target=steps, args=(s,)) for s in sims]
        for t in threads:
            t.start()
        for t in threads:
            t.join(timeout=60)
        assert sims[1].getSimulationTime() - start == pytest.approx(0.5)  # 10 passes, not 20
        sims[0].stopSimulation()
        del sims, clients
        time.sleep(0.1)


@pytest.mark.needs_shared("data", "scenes", "course", "Scene_CheckPoint1.py")
def test_a_course_checkpoint_script_in_its_own_old_numpy(cache, tmp_path):
    """The course's check-point script and helper build ragged numpy arrays, which numpy 1.24
    refuses: with --python they run in an environment of their own and move the arms."""
    from shared_data import shared

    folder = shared("data", "scenes", "course")
    python = python_env(cache, "numpy-1.23", ["numpy<1.24", "scipy<1.12", "transforms3d"])
    done = subprocess.run(
        [sys.executable, "-m", "sims.remote_api", "run", str(folder / "Scene_CheckPoint1.py"),
         "--scene", str(folder / "Scene_CheckPoint1.ttt"), "--python", str(python)],
        capture_output=True, text=True, timeout=300, cwd=REPO,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    thetas = [
        float(line.rsplit("=", 1)[1]) for line in done.stdout.splitlines() if "theta =" in line
    ]
    assert len(thetas) == 24  # every joint read twice: before and after the moves
    # the script's commands: theta + (-30, +30, +30, -30, -45, +45, +45, -45, +60, -, +90,
    # -72) degrees from the arms' start (all joints at 0 in the scene)
    expected = [-30, 30, 30, -30, -45, 45, 45, -45, 60, 0, 90, -72]
    assert [round(math.degrees(v)) for v in thetas[12:]] == expected, thetas


HOME_POSE = "-0.194\n0\n0.6511\n0\n-90\n0\n" * 3  # the UR3's end pose at zero joint angles


@pytest.mark.needs_shared("data", "scenes", "course2", "Scene_CheckPoint3.py")
def test_the_course2_checkpoint_script_with_its_poses_on_stdin(cache, tmp_path):
    """Scene_CheckPoint3.py asks for three goal poses (input()), solves its own inverse
    kinematics with the helper's ragged arrays and sends the joint angles. With numpy < 1.24 it
    gets past those arrays (numpy 1.24 refuses them); its solver then inverts the object array
    they make (np.linalg.inv), which every numpy refuses (1.16, 1.18, 1.23 tried) as soon as it
    must iterate. The poses given are the arm's home pose: when the arm is there the script
    sends the angles it read and the arm holds them; when the scene's own script has moved the
    arm, the run ends in the course script's own solver, never in the emulation."""
    from shared_data import shared

    folder = shared("data", "scenes", "course2")
    python = python_env(cache, "numpy-1.23", ["numpy<1.24", "scipy<1.12", "transforms3d"])
    poses = tmp_path / "poses.txt"
    poses.write_text(HOME_POSE, encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-m", "sims.remote_api", "run", str(folder / "Scene_CheckPoint3.py"),
         "--scene", str(folder / "Scene_CheckPoint3.ttt"), "--python", str(python),
         "--stdin", str(poses)],
        capture_output=True, text=True, timeout=300, cwd=REPO,
    )  # fmt: skip
    readings = [line for line in done.stdout.splitlines() if "theta =" in line]
    assert len(readings) >= 6  # handles found, the simulation started, all six joints read
    assert "VisibleDeprecationWarning" in done.stderr  # the ragged arrays were made, not refused
    if done.returncode == 0:
        assert done.stdout.count("P_final [-0.194   0.      0.6511]") == 3
        thetas = [float(line.rsplit("=", 1)[1]) for line in readings]
        assert len(thetas) == 18 and all(abs(t) < 0.01 for t in thetas[-6:])
    else:
        tail = done.stderr.strip().splitlines()
        assert any('Scene_CheckPoint3.py", line 457' in line for line in tail), tail[-12:]
        assert "inv" in done.stderr and "dtype('O')" in done.stderr
    assert "connections (served on loopback): 127.0.0.1:19997" in done.stderr


SIM_PY_WITH_LIBRARY = """\
# a sim.py of the script's own that loads remoteApi.so beside it, as CoppeliaSim's does
import ctypes as ct, os
lib = ct.CDLL(os.path.join(os.path.dirname(os.path.abspath(__file__)), "remoteApi.so"))
lib.simxStart.argtypes = [ct.c_char_p, ct.c_int32, ct.c_ubyte, ct.c_ubyte, ct.c_int32, ct.c_int32]
lib.simxGetObjectHandle.argtypes = [ct.c_int32, ct.c_char_p, ct.POINTER(ct.c_int32), ct.c_int32]
lib.simxGetJointPosition.argtypes = [ct.c_int32, ct.c_int32, ct.POINTER(ct.c_float), ct.c_int32]
lib.simxSetJointTargetPosition.argtypes = [ct.c_int32, ct.c_int32, ct.c_float, ct.c_int32]
simx_opmode_blocking = 0x010000
def simxStart(a, p, w, d, t, c):
    return lib.simxStart(a.encode(), p, w, d, t, c)
def simxGetObjectHandle(cid, name, mode):
    h = ct.c_int32()
    return lib.simxGetObjectHandle(cid, name.encode(), ct.byref(h), mode), h.value
def simxGetJointPosition(cid, h, mode):
    v = ct.c_float()
    return lib.simxGetJointPosition(cid, h, ct.byref(v), mode), v.value
simxSetJointTargetPosition = lib.simxSetJointTargetPosition
simxSynchronous = lib.simxSynchronous
simxSynchronousTrigger = lib.simxSynchronousTrigger
simxStartSimulation = lib.simxStartSimulation
simxFinish = lib.simxFinish
"""


def test_python_run_uses_the_client_library_beside_the_script(cache, tmp_path):
    """--python: a script whose folder holds sim.py and a Linux remoteApi.so talks to the
    legacy server over TCP with them (inside the run's own network namespace)."""
    import shutil

    shutil.copyfile(extapi_library(cache), tmp_path / "remoteApi.so")
    (tmp_path / "sim.py").write_text(SIM_PY_WITH_LIBRARY, encoding="utf-8")
    script = tmp_path / "arm.py"
    script.write_text(
        textwrap.dedent(
            """\
            import sim
            cid = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)
            assert cid == 0, cid
            rc, h = sim.simxGetObjectHandle(cid, 'ShoulderMotor', sim.simx_opmode_blocking)
            sim.simxSynchronous(cid, 1)
            sim.simxStartSimulation(cid, sim.simx_opmode_blocking)
            sim.simxSetJointTargetPosition(cid, h, 2.0, sim.simx_opmode_blocking)
            for _ in range(40):
                sim.simxSynchronousTrigger(cid)
            print('angle', round(sim.simxGetJointPosition(cid, h, sim.simx_opmode_blocking)[1], 3))
            sim.simxFinish(cid)
            """
        ),
        encoding="utf-8",
    )
    done = subprocess.run(
        [sys.executable, "-m", "sims.remote_api", "run", str(script), "--scene", "2w1a",
         "--python", sys.executable],
        capture_output=True, text=True, timeout=120, cwd=REPO,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "angle 2.0" in done.stdout
    assert "connections (served on loopback): 127.0.0.1:19997" in done.stderr
