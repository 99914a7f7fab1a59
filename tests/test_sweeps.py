"""Sweeps on the local executor (sims/sweeps/, sims/runs.py, `sitegen remote-api sweep`).

The runs are the project's own 2W1A experiments (examples/sweeps/) on the bundled scene, cut
short with --seconds where the test allows; Ray is tested in test_sweeps_ray.py.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from located.diagnostics import LocatedError
from sims import runs
from sims.sweeps import results
from sims.sweeps.one_run import parse_results
from sims.sweeps.plan import derived_seed, parse_grid, parse_seeds, plan_runs

ROOT = Path(__file__).resolve().parents[1]
REACH = ROOT / "examples" / "sweeps" / "arm_random_reach.py"
START = (-0.02, 0.0)  # the bundled 2W1A's body at rest, x and y (m), within 1 cm


def _rows(path: Path) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(path.read_text(encoding="utf-8"))))


def test_plan_seeds_grid_and_derived_seeds():
    assert parse_seeds("0:4") == [0, 1, 2, 3]
    assert parse_seeds("10:20:5") == [10, 15]
    assert parse_seeds("3,1") == [3, 1]
    planned = plan_runs([7, 8], parse_grid(["a=1,2", "b=x"]))
    assert [(r.index, r.seed, r.args) for r in planned] == [
        (0, 7, (("a", "1"), ("b", "x"))),
        (1, 7, (("a", "2"), ("b", "x"))),
        (2, 8, (("a", "1"), ("b", "x"))),
        (3, 8, (("a", "2"), ("b", "x"))),
    ]
    assert planned[1].argv() == ["--a=2", "--b=x"]
    assert planned[1].env() == {
        "SWEEP_A": "2",
        "SWEEP_B": "x",
        "SWEEP_INDEX": "1",
        "SWEEP_SEED": "7",
    }
    grid = plan_runs(None, parse_grid(["g=1,2,3"]), sweep_seed=5)
    assert [r.seed for r in grid] == [derived_seed(5, i) for i in range(3)]
    assert len({r.seed for r in grid}) == 3 and derived_seed(5, 0) != derived_seed(6, 0)
    seeded = plan_runs(None, parse_grid(["seed=4,9"]))
    assert [r.seed for r in seeded] == [4, 9] and seeded[0].argv() == []


def test_plan_bad_input_names_option_file_line_and_field(tmp_path):
    with pytest.raises(LocatedError) as bad:
        parse_seeds("0:x")
    assert str(bad.value).startswith("--seeds: error: '0:x'")
    with pytest.raises(LocatedError, match="--grid: error: '1a=2'"):
        parse_grid(["1a=2"])
    table = tmp_path / "runs.csv"
    table.write_text("gain,seed\n0.5,1\n\n0.7\n", encoding="utf-8")
    with pytest.raises(LocatedError) as bad:
        plan_runs(None, (), table)
    assert str(bad.value) == f"{table}:4: error: row: 1 values for 2 columns"
    table.write_text("gain,seed\n0.5,one\n", encoding="utf-8")
    with pytest.raises(LocatedError) as bad:
        plan_runs(None, (), table)
    assert str(bad.value) == f"{table}:2: error: seed: 'one' is not a whole number"


def test_result_lines():
    text = 'x\nRESULT a=1 b=2.5 c=text d="two words" e=true\n  RESULT a=3\nRESULTS z=1\n'
    assert parse_results(text) == {"a": 3, "b": 2.5, "c": "text", "d": "two words", "e": True}


def test_seed_sweep_same_results_with_one_and_two_workers(tmp_path):
    """The project's own random-target experiment over 4 seeds: every run reports how far the
    body moved; results.csv is byte for byte the same with 1 and 2 workers, and what the runs
    printed agrees with where the final state puts the robot."""
    settings = runs.settings_for(REACH, "2w1a", label="arm_random_reach.py")
    planned = plan_runs(range(4))
    one = runs.sweep(settings, planned, tmp_path / "one", "local", workers=1)
    two = runs.sweep(settings, planned, tmp_path / "two", "local", workers=2)
    assert one.csv.read_bytes() == two.csv.read_bytes()
    rows = _rows(one.csv)
    assert [r["index"] for r in rows] == ["0", "1", "2", "3"]
    assert [r["seed"] for r in rows] == ["0", "1", "2", "3"]
    assert all(r["status"] == "ok" and r["exit_code"] == "0" for r in rows)
    assert all(abs(float(r["sim_seconds"]) - 6.7) < 0.11 for r in rows)  # 3 moves of 2 s
    distances = [float(r["distance"]) for r in rows]
    assert len(set(distances)) == 4  # different seeds, different targets
    for r in rows:  # the printed distance is the final state's, within a pass of motion
        moved = math.hypot(float(r["final_x"]) - START[0], float(r["final_y"]) - START[1])
        assert abs(moved - float(r["distance"])) < 0.02
        assert 0.0 <= float(r["final_z"]) < 0.3  # on the floor
        assert 0 <= math.degrees(float(r["final_ShoulderMotor"])) % 360 <= 360
    lines = one.jsonl.read_text(encoding="utf-8").splitlines()
    assert [json.loads(x)["index"] for x in lines] == [0, 1, 2, 3]
    assert "wall_seconds" in lines[0] and "wall_seconds" not in one.csv.read_text()


def test_arguments_result_file_failures_and_cut(tmp_path):
    """Arguments reach sys.argv and the environment, a JSON result file is merged, a failing
    run is a row with its error (line named) while the others go on, --seconds cuts a run."""
    script = tmp_path / "probe.py"
    script.write_text(
        textwrap.dedent(
            """\
            import json, os, random, sys, time
            import sim
            client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
            sim.simxStartSimulation(client, sim.simx_opmode_blocking)
            gain = float(os.environ["SWEEP_GAIN"])
            if gain < 0:
                raise ValueError("negative gain")
            time.sleep(float(os.environ.get("SWEEP_WAIT", "0.5")))
            print("RESULT argv=" + ",".join(sys.argv[1:]), "r=%d" % random.randint(0, 10**6))
            with open(os.environ["SWEEP_RESULT_FILE"], "w") as fh:
                json.dump({"double": 2 * gain, "seed": int(os.environ["SWEEP_SEED"])}, fh)
            """
        ),
        encoding="utf-8",
    )
    settings = runs.settings_for(script, "2w1a", seconds=2.0, label="probe.py")
    planned = plan_runs([11], parse_grid(["gain=1.5,-1", "wait=0.5,5"]))
    out = runs.sweep(settings, planned, tmp_path / "out", "local", workers=2)
    rows = _rows(out.csv)
    assert [(r["gain"], r["wait"], r["status"]) for r in rows] == [
        ("1.5", "0.5", "ok"),
        ("1.5", "5", "cut"),
        ("-1", "0.5", "failed"),
        ("-1", "5", "failed"),
    ]
    ok = rows[0]
    assert ok["argv"] == "--gain=1.5,--wait=0.5" and ok["double"] == "3.0"
    assert ok["result_seed"] == "11"  # a result named like a column keeps its own column
    assert rows[1]["sim_seconds"] == "2.0" and rows[1]["double"] == ""
    assert rows[2]["error"] == "probe.py:7: ValueError: negative gain"


def test_cli_sweep_writes_results_and_reports(tmp_path):
    cmd = [sys.executable, "-m", "sitegen", "remote-api", "sweep", str(REACH), "--scene", "2w1a"]
    done = subprocess.run(
        [*cmd, "--seeds", "0:2", "--seconds", "1", "--out", str(tmp_path / "o"), "-q"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert "[sweep] 2 runs, 0 failed, on local" in done.stderr
    assert len(_rows(tmp_path / "o" / "results.csv")) == 2
    bad = tmp_path / "runs.csv"
    bad.write_text("gain\n1\n2,3\n", encoding="utf-8")
    done = subprocess.run(
        [*cmd, "--args-file", str(bad)], capture_output=True, text=True, cwd=tmp_path, timeout=120
    )
    assert done.returncode == 2
    lines = [x for x in done.stderr.splitlines() if not x.startswith("pybullet build time")]
    assert lines == [f"{bad}:3: error: row: 2 values for 1 columns"]


def test_asking_for_ray_without_ray_is_one_line(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray fails as if not installed
    with pytest.raises(RuntimeError, match=r"^Ray is not installed: pip install ray"):
        runs.make_executor("ray")
    from sims.sweeps.cli import main

    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    code = main([str(REACH), "--scene", "2w1a", "--seeds", "0:1", "--ray", "--out", str(tmp_path)])
    assert code == 2
    assert err.getvalue().splitlines()[-1] == (
        "error: Ray is not installed: pip install ray (sitegen's [ray] extra)"
    )


def test_results_table_is_ordered_and_stable():
    from sims.sweeps.one_run import RunRecord

    a = RunRecord(1, 5, {"k": "2"}, "ok", 0, results={"v": 0.1, "w": [1, 2]})
    b = RunRecord(0, 4, {"k": "1"}, "failed", 1, error="x.py:3: boom", results={"v": 1})
    text = results.csv_text([b, a])
    assert text.splitlines() == [
        "index,seed,k,status,exit_code,sim_seconds,simulations,v,w,error",
        "0,4,1,failed,1,0.0,0,1,,x.py:3: boom",
        '1,5,2,ok,0,0.0,0,0.1,"[1,2]",',
    ]


def test_progress_shows_done_failed_running_rate_and_time_left():
    from sims.sweeps.progress import SweepProgress

    out = io.StringIO()
    shown = SweepProgress(4, stream=out, live=False, every=0.0)
    for i in range(3):
        shown.started(i)
    shown.finished({"index": 0, "status": "ok", "error": ""})
    shown.finished({"index": 1, "status": "failed", "error": "x.py:3: ValueError: no"})
    line = shown.line()
    assert re.match(r"runs: 2/4 done, 1 failed, 1 running, [\d.]+ runs/s, about \d+ s left$", line)
    assert "run 1 failed: x.py:3: ValueError: no" in out.getvalue().splitlines()
    shown.finished({"index": 2, "status": "cut", "error": ""})
    shown.started(3)
    shown.finished({"index": 3, "status": "ok", "error": ""})
    shown.close()
    assert re.search(r"runs: 4/4 done, 1 failed, 0 running, [\d.]+ runs/s, \d+ s$", out.getvalue())


def test_a_small_genetic_algorithm_evaluates_its_population_in_parallel():
    """examples/sweeps/ga_crawl.py through sims.runs.evaluate: every candidate is a real run
    (the distance it crawled), elitism never loses the best, and the search is reproducible."""
    import importlib.util

    path = ROOT / "examples" / "sweeps" / "ga_crawl.py"
    spec = importlib.util.spec_from_file_location("ga_crawl", path)
    ga = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ga)
    with runs.make_executor("local", workers=2) as executor:
        history, scored = ga.search(4, 2, executor, seed=3, strokes=1)
        again = runs.evaluate(ga.SCRIPT, "2w1a", [{**history[-1][2], "strokes": 1}], executor)
    assert len(history) == 2 and len(scored) == 4
    assert history[1][1] >= history[0][1] > 0.0
    assert all(0.0 <= fitness < 1.0 for fitness, _, _ in scored)
    assert again[0].ok and again[0].results["distance"] == history[-1][1]
