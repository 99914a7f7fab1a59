"""The course's CoppeliaSim scripts and this project's examples, run unchanged on pybullet.

The course scripts are read from shared/seeds/scripts (never copied into the repo).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import re
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from sims.remote_api import api
from sims.remote_api.cli import main
from sims.remote_api.extras import UNSUPPORTED
from sims.remote_api.runner import run_script

REPO = Path(__file__).resolve().parents[1]
SCRIPTS = Path(__file__).resolve().parents[1].parent / "shared" / "seeds" / "scripts"
TWO_W1A = SCRIPTS / "task2_2w1a_random.py"
CART = SCRIPTS / "task2-2_cart_velocity.py"
EXAMPLES = REPO / "examples" / "remote_api"

# The course scripts come from ../shared (tests/shared_data.py): skipped without it, failing
# under CI; the project's own examples below need nothing outside the repository.
needs_cart_script = pytest.mark.needs_shared("seeds", "scripts", CART.name)

POSITION = re.compile(r"2w1a position: \(x = (\S+), y = (\S+)\)")


class _NoSocket(socket.socket):
    def __init__(self, *args, **kwargs):
        raise AssertionError("the remote API emulation created a socket")


@pytest.fixture(scope="module")
def two_w1a_run():
    """One run of the 2W1A course script (seed 7), with sockets forbidden throughout
    (captured by hand: capsys is function-scoped)."""
    from shared_data import shared

    shared("seeds", "scripts", TWO_W1A.name)
    out, err = io.StringIO(), io.StringIO()
    saved = socket.socket
    socket.socket = _NoSocket
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            result = run_script(TWO_W1A, "2w1a", seed=7)
    finally:
        socket.socket = saved
    return result, out.getvalue(), err.getvalue()


def test_2w1a_script_prints_like_in_coppeliasim(two_w1a_run):
    result, out, err = two_w1a_run
    assert result.exit_code == 0, result.message
    lines = out.splitlines()
    assert lines[0] == "Start"
    assert lines[1] == "Connected to remote API server"
    assert lines[-1] == "End"
    assert out.count("----- Simulation started -----") == 3
    assert out.count("----- Simulation ended -----") == 3
    assert out.count("Motors target positions: ") == 15
    assert out.count("Motors reached positions: ") == 15
    assert len(POSITION.findall(out)) == 18
    assert "Could not add a message" not in out and "Failed connecting" not in out
    # the first streaming read of each simulation: novalue with zeros the very first time,
    # then the stream's latest value (the reset pose) in the later simulations
    first = POSITION.findall(out)[0]
    assert first == ("0.0", "0.0")
    assert "[sim status bar] teacher" in err
    assert result.simulations == 3
    assert [(c.address, c.port) for c in result.connections] == [("192.168.192.1", 19997)]


def test_2w1a_body_moves_and_time_is_virtual(two_w1a_run):
    result, out, _ = two_w1a_run
    # about 3 x (5 x 5 s + blocking calls) simulated, the sleeps took no wall time
    assert 75 <= result.sim_time <= 85
    assert result.clock_time >= 78  # 15 x 5 s + 3 x 1 s of sleeps
    assert result.wall_time < 20
    start = (-0.0201, 0.0)
    moved = [math.dist(start, (float(x), float(y))) for x, y in POSITION.findall(out)]
    assert max(moved) > 0.02  # the body was pushed around by its arm
    per_run = {}
    for s in result.samples:
        per_run.setdefault(s.run, []).append(math.dist(start, (s.x, s.y)))
    assert sorted(per_run) == [1, 2, 3]
    assert max(max(d) for d in per_run.values()) > 0.02


def test_seed_makes_runs_reproducible(two_w1a_run, capsys):
    _, out, _ = two_w1a_run
    again = run_script(TWO_W1A, "2w1a", seed=7)
    assert again.ok
    assert capsys.readouterr().out == out
    other = run_script(TWO_W1A, "2w1a", seed=8)
    assert other.ok
    targets = re.findall(r"Motors target positions: .*", capsys.readouterr().out)
    assert targets != re.findall(r"Motors target positions: .*", out)


@needs_cart_script
def test_cart_script_drives_backwards(capsys, monkeypatch):
    monkeypatch.setattr(socket, "socket", _NoSocket)
    result = run_script(CART, "cart", seed=0, after=3.0)
    out = capsys.readouterr().out
    assert result.exit_code == 0, result.message
    assert out.strip() == "Connected to remote server"
    assert [(c.address, c.port) for c in result.connections] == [("127.0.0.1", 19999)]
    first, last = result.samples[0], result.samples[-1]
    assert 3.0 <= result.sim_time <= 3.5  # blocking calls wait for a pass (50 ms) each
    # forward is the cart's +x: -1 rad/s on 28 mm wheels is about 2.8 cm/s backwards
    backwards = -(
        (last.x - first.x) * math.cos(first.heading) + (last.y - first.y) * math.sin(first.heading)
    )
    assert 0.05 < backwards < 0.12
    assert abs(last.heading - first.heading) < 0.1


@needs_cart_script
def test_realtime_paces_by_the_wall_clock(capsys):
    """Real time: the simulation never runs ahead of the wall clock (unpaced, this run takes
    a quarter of its simulated time). Only "not ahead" is asserted: how closely a loaded
    machine keeps up is a benchmark's question, not a test's."""
    result = run_script(CART, "cart", realtime=True, after=0.6)
    assert result.ok, result.message
    assert result.sim_time > 0.6
    assert result.wall_time >= result.sim_time and result.clock_time >= result.sim_time - 0.01


@needs_cart_script
def test_cli_runs_a_course_script_in_a_subprocess():
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "sims.remote_api",
            "run",
            str(CART),
            "--scene",
            "cart",
            "--after",
            "1",
        ],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "Connected to remote server"
    assert "127.0.0.1:19999" in proc.stderr and "recorded, not contacted" in proc.stderr


# --- the project's own examples -------------------------------------------------------------------
EXAMPLE_SCENES = {
    "streaming_and_modes.py": "2w1a",
    "error_codes.py": "2w1a",
    "synchronous.py": "2w1a",
    "objects_and_signals.py": "2w1a",
    "cart_obstacles.py": "cart",
    "rover_scene.py": str(REPO / "data" / "scenes" / "rover.simscene.xml"),
    "arm_random_moves.py": "2w1a",  # the site's clips (tests/test_sims_examples.py)
    "cart_velocity.py": "cart",
    "scene_changes.py": "2w1a",
}


def _run_example(name, capsys, **kw):
    result = run_script(EXAMPLES / name, EXAMPLE_SCENES[name], **kw)
    captured = capsys.readouterr()
    assert result.exit_code == 0, result.message
    return dict(line.split(": ", 1) for line in captured.out.splitlines()), captured.err


def test_examples_cover_every_supported_function():
    used = set()
    for path in EXAMPLES.glob("*.py"):
        used |= set(re.findall(r"\bsim\.(simx[A-Za-z0-9]+)\b", path.read_text(encoding="utf-8")))
    functions = {n for n in api.__all__ if n.startswith("simx") and not n.startswith("simx_")}
    supported = functions - set(UNSUPPORTED)
    assert not supported - used, f"not shown by any example: {sorted(supported - used)}"
    assert set(EXAMPLE_SCENES) == {p.name for p in EXAMPLES.glob("*.py")}


def test_example_streaming_and_modes(capsys):
    out, err = _run_example("streaming_and_modes.py", capsys)
    assert out["streaming first call"] == "1 [0.0, 0.0, 0.0]"
    assert out["buffer after streaming"].startswith("0 [-0.0201")
    assert out["buffer without stream"] == "1 0.0"
    assert out["blocking joint position"] == "0 150.0"
    assert out["buffer after blocking"] == "1"
    assert (out["oneshot status bar 1"], out["oneshot status bar 2"]) == ("1", "0")
    assert (out["oneshot getter first"], out["oneshot getter second"]) == ("1", "0 150.0")
    assert out["shoulder (buffer)"] == "0 60"
    assert (out["remove"], out["remove again"], out["buffer after remove"]) == ("0", "1", "1")
    assert out["shoulder after stop"] == "150"
    assert out["connection id after finish"] == "-1"
    assert "[sim status bar] hello" in err


def test_example_error_codes(capsys):
    out, err = _run_example("error_codes.py", capsys)
    assert out["before simxStart"] == "(64, 0)"
    assert out["client ids"] == "0 1"
    assert out["unknown name"] == "(8, 0)"
    assert out["name with #0"] == "0"
    assert out["invalid handle"] == "(8, [0.0, 0.0, 0.0])"
    assert out["not a joint"] == "(8, 0.0)" and out["set on not a joint"] == "8"
    assert (out["oneshot error 1"], out["oneshot error 2"]) == ("1", "8")
    assert out["illegal opmode"] == "4"
    assert out["bad client id"] == "64"
    assert out["unsupported"] == "(32, 0, 0)"
    assert out["unknown function"] == "32"
    assert out["missing signal"] == "(8, 0.0)"
    assert out["remote error bit set"] == "True"
    assert "simxDisplayDialog is not supported" in err
    assert "simxTeleportRobot is not a legacy remote API function" in err


def test_example_scene_changes(capsys):
    """Every function there answers with a code (0 done, 8 not possible here), the 4.x names
    answer as the old ones, and a query nobody answers times out (2)."""
    out, _ = _run_example("scene_changes.py", capsys)
    codes = {k: v.strip("()").split(",")[0].split()[0] for k, v in out.items()}
    assert all(c in ("0", "8") for k, c in codes.items() if k != "query"), codes
    for key in [k for k in out if k.endswith(" (4.x)")]:
        base = key[: -len(" (4.x)")]
        if base in out:
            assert out[key] == out[base], key
    assert out["query"] == "2 b''"
    assert out["remove model"] == "8" and out["load scene"] == "8"  # nothing of that name
    assert out["float parameter"] == "(0, 0.05000000074505806)"


def test_example_synchronous(capsys):
    out, _ = _run_example("synchronous.py", capsys)
    assert out["simulation step (s)"] == "0.05"
    assert out["simulation time after each trigger (ms)"] == "[50, 100, 150, 200, 250]"
    assert out["wrist moved from 250 towards 200"] == "0 True"
    assert out["server state running/paused bits"] == "1 1 1"
    assert out["paused bit after resume"] == "0"
    assert out["running bit after stop"] == "0"


def test_example_objects_and_signals(capsys):
    out, _ = _run_example("objects_and_signals.py", capsys)
    assert out["objects"] == "0 31"  # every object of 2w1a.ttt: floor, cameras, lights...
    assert out["parent of ArmRespondable is ShoulderMotor"] == "True"
    assert out["parent of 2W1A"] == "-1"
    # 2w1a.ttt: the body frame's z along world x, its y along world -y (gimbal lock at 90)
    assert out["body orientation (deg)"] in ("[-180, 90, 0]", "[180, 90, 0]")
    assert out["body now at"] == "[0.5, 0.2, 0.07]"
    assert out["move a link"] == "8"
    assert out["shoulder now (deg)"] == "100"
    assert out["string signal"] == "(0, bytearray(b'2W1A-robot'))"
    assert out["cleared"] == "8" and out["float cleared"] == "8"
    assert out["stream"] == "[1.5, -2.0] [7]"
    assert out["version"] == "(0, 40200)"
    assert out["gravity z"] == "-9.81"


def test_example_rover_scene_roams_its_arena(capsys):
    out, err = _run_example("rover_scene.py", capsys)
    assert out["handles found"] == "True"
    assert out["max torque (N*m)"] == "0.4"
    assert out["spherical matrix on a wheel"] == "8"
    assert out["camera image"] == "0 [64, 48] True"
    assert out["camera mean brightness > 30"] == "True"
    assert out["wheel joint matrix is a rotation about z"] == "True"
    assert out["went more than 1.5 m away from the start"] == "True"
    assert int(out["turns"]) >= 1 and out["nearest seen (m) below 0.3"] == "True"
    assert "lacks" not in err and "not implement" not in err


def test_example_cart_obstacles(capsys):
    out, err = _run_example("cart_obstacles.py", capsys, seed=3)
    assert out["simulation running"] == "True"
    assert out["start refused"] == "8" and out["stop refused"] == "8"
    assert out["joints"] == "2"
    assert out["travelled"] == "True"
    assert int(out["turns"]) >= 1
    assert "temporary one" in err


# --- failures, exits and time limits --------------------------------------------------------------
def _script(tmp_path, text, name="student.py"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_a_raising_script_names_its_file_and_line(tmp_path, capsys):
    path = _script(tmp_path, "import sim\nx = 1\nraise ValueError('bad value')\n")
    result = run_script(path, "2w1a")
    assert result.exit_code == 1
    assert result.message == f"{path}:3: ValueError: bad value"
    code = main(["run", str(path), "--scene", "2w1a"])
    assert code == 1
    err = capsys.readouterr().err
    assert f"error: {path}:3: ValueError: bad value" in err


def test_a_syntax_error_names_its_line(tmp_path):
    path = _script(tmp_path, "import sim\n\nif True\n    pass\n")
    result = run_script(path, "2w1a")
    assert result.exit_code == 1 and result.message.startswith(f"{path}:3: SyntaxError")


def test_sys_exit_is_passed_through(tmp_path, capsys):
    assert run_script(_script(tmp_path, "import sys\nsys.exit(3)\n"), "cart").exit_code == 3
    assert run_script(_script(tmp_path, "import sys\nsys.exit()\n"), "cart").exit_code == 0
    result = run_script(_script(tmp_path, "import sys\nsys.exit('Could not connect')\n"), "cart")
    assert (result.exit_code, result.message) == (1, "Could not connect")
    assert "Could not connect" in capsys.readouterr().err


def test_virtual_time_limit_stops_a_sleeping_loop(tmp_path):
    path = _script(tmp_path, "import time\nwhile True:\n    time.sleep(1)\n")
    result = run_script(path, "2w1a", timeout=30)
    assert result.exit_code == 124 and result.timed_out
    assert result.message.startswith(f"{path}:3: stopped:")
    assert "simulated time" in result.message and result.wall_time < 5


def test_wall_time_limit_stops_a_busy_loop(tmp_path):
    path = _script(tmp_path, "n = 0\nwhile True:\n    n += 1\n")
    result = run_script(path, "2w1a", timeout=1.0)
    assert result.exit_code == 124
    assert re.match(rf"{re.escape(str(path))}:[23]: stopped: .*wall-clock time", result.message)
    assert result.wall_time < 5


def test_script_environment_is_restored(tmp_path, capsys):
    import random
    import time

    helper = _script(tmp_path, "VALUE = 42\n", name="helper_mod.py")
    path = _script(
        tmp_path,
        "import sys, vrep, helper_mod, simConst\n"
        "print(sys.argv[1:], helper_mod.VALUE, vrep.simx_opmode_streaming,"
        " simConst.sim_handle_all, __name__)\n",
    )
    state = random.getstate()
    saved_path, real_sleep = list(sys.path), time.sleep
    result = run_script(path, "2w1a", argv=["a", "b"])
    assert result.ok, result.message
    assert capsys.readouterr().out.strip() == "['a', 'b'] 42 131072 -2 __main__"
    assert sys.path == saved_path and time.sleep is real_sleep
    assert random.getstate() == state
    assert "helper_mod" not in sys.modules and "sim" not in sys.modules
    del helper


def test_network_is_blocked_for_the_script(tmp_path):
    path = _script(
        tmp_path, "import socket\ns = socket.socket()\ns.connect(('192.168.192.1', 19997))\n"
    )
    result = run_script(path, "2w1a")
    assert result.exit_code == 1 and "network access is disabled" in result.message


# --- recording -----------------------------------------------------------------------------------
@needs_cart_script
def test_record_writes_gallery_files(tmp_path, capsys):
    out = tmp_path / "clips" / "cart.webm"
    code = main(
        [
            "run",
            str(CART),
            "--scene",
            "cart",
            "--after",
            "1.5",
            "--record",
            str(out),
            "--size",
            "160x120",
            "--fps",
            "10",
            "-q",
        ]
    )
    captured = capsys.readouterr()
    assert code == 0, captured.err
    for suffix in (".webm", ".png", ".csv", ".json", ".svg"):
        assert out.with_suffix(suffix).stat().st_size > 0, suffix
    data = json.loads(out.with_suffix(".json").read_text(encoding="utf-8"))
    assert data["kind"] == "script" and data["scene"] == "cart"
    assert any(e.get("line") == "Connected to remote server" for e in data["events"])
    xs = [row[data["columns"].index("x")] for row in data["samples"]]
    assert xs[-1] < xs[0] - 0.02  # backwards
    from sims.video import probe

    info, _ = probe(out)
    assert info.frames >= 15 and (info.width, info.height) == (160, 120)


def test_script_clip_kind_renders_and_keys_by_content(tmp_path):
    from sims import clip_cache
    from sims.clips import ClipSpec, render_clips, spec_fields
    from sims.remote_api.script_clips import script_plan

    script = _script(
        tmp_path,
        (EXAMPLES / "cart_obstacles.py").read_text(encoding="utf-8").replace("< 20", "< 2"),
        name="drive.py",
    )
    spec = ClipSpec(
        name="drive", scenario=str(script), kind="script", width=160, height=120, fps=10, seed=3
    )
    plan = script_plan(spec)
    assert plan.scene == "cart" and 2.0 < plan.length() < 3.5
    key = clip_cache.clip_key(spec_fields(spec, plan.seed, plan.params), plan.hash_files)
    script.write_text(script.read_text(encoding="utf-8") + "\n# changed\n", encoding="utf-8")
    plan2 = script_plan(spec)
    assert clip_cache.clip_key(spec_fields(spec, plan2.seed, plan2.params), plan2.hash_files) != key
    [result] = render_clips([spec], tmp_path / "cache", jobs=1)
    assert result.ok, result.error
    assert result.files["video"].stat().st_size > 0
    assert result.meta["scene"] == "cart"


def test_a_script_clip_without_seconds_runs_only_when_rendered(tmp_path, monkeypatch):
    """Every build plans every clip (to find its cache key): planning a script clip without
    ``seconds`` runs nothing; rendering it runs the script twice (the dry run that measures
    its length, then the filmed run), and the measured length is the filmed one."""
    from sims.clips import ClipSpec, planned
    from sims.recording import record
    from sims.remote_api import script_clips

    runs: list[str] = []
    real = script_clips.run_script

    def counted(*args, **kwargs):
        runs.append("world" if kwargs.get("world") is not None else "dry")
        return real(*args, **kwargs)

    monkeypatch.setattr(script_clips, "run_script", counted)
    script = _script(
        tmp_path,
        (EXAMPLES / "cart_obstacles.py").read_text(encoding="utf-8").replace("< 20", "< 2"),
        name="drive.py",
    )
    spec = ClipSpec(name="drive", scenario=str(script), kind="script", fps=10, seed=5)
    _, plan, key = planned(spec)
    _, _, again = planned(spec)
    assert runs == [] and key == again and not plan.length_known
    length = plan.length()
    assert runs == ["dry"] and plan.length() == length and 2.0 < length < 3.5
    recording, _ = record(plan, fps=10)
    assert runs == ["dry", "world"]
    assert recording.column("t")[-1] == pytest.approx(length - 0.1, abs=0.15)
