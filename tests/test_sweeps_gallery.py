"""A sweep in a site (``sims: sweeps:``): built strict like a clip, cached by its inputs, shown
as a page with its table, plots and best run, whose clip replays that very run."""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path

import pytest
from sitegen_helpers import REPO, write_tree

from sitegen.build import BuildOptions, build
from sitegen.config import parse_config
from sitegen.errors import BuildError

REACH = (REPO / "examples" / "sweeps" / "arm_random_reach.py").read_text(encoding="utf-8")
CONFIG = (
    "title: t\nsims:\n  size: 96x64\n  fps: 8\n  sweeps:\n"
    "    - {name: reach, title: Reach, script: reach.py, scene: 2w1a, seeds: 0:4, seconds: 2,\n"
    "       key: final_x, best: 1}\n"
)


def test_a_sweep_builds_as_a_page_with_table_plots_and_its_best_run_as_a_clip(tmp_path):
    source = write_tree(
        tmp_path / "src",
        {"sitegen.yml": CONFIG, "reach.py": REACH, "content/index.md": "# Home\n\nhi\n"},
    )
    out = tmp_path / "site"
    lines: list[str] = []
    report = build(BuildOptions(source=source, output=out, strict=True, log=lines.append))
    assert [str(d) for d in report.diagnostics] == []
    assert "sweep reach: 4 runs" in lines
    rows = list(csv.DictReader(io.StringIO((out / "sweeps/reach/results.csv").read_text())))
    assert [r["seed"] for r in rows] == ["0", "1", "2", "3"]
    assert all(r["status"] == "cut" and r["sim_seconds"] == "2.0" for r in rows)
    best = max(rows, key=lambda r: float(r["final_x"]))
    page = (out / "gallery" / "reach.html").read_text(encoding="utf-8")
    body = page[page.index('<div class="body">') :]
    # the table lists the runs best first (key final_x, order max)
    shown = re.findall(r"<tr><td>(\d+)</td>", body)
    ranked = sorted(rows, key=lambda r: (-float(r["final_x"]), int(r["index"])))
    assert shown == [r["index"] for r in ranked]
    assert body.count("<circle") == 4 and body.count("fill:var(--accent") >= 2  # best + bars
    assert "var(--fg" in body and "#fff" not in body.split("<svg", 1)[1][:200]
    # the best run's clip is that run again: the robot ends where the sweep's run ended
    clip = out / "sweeps" / "reach" / f"run-{best['index']}"
    assert (clip / "clip.webm").stat().st_size > 1000
    assert f'src="../sweeps/reach/run-{best["index"]}/clip.webm"' in body
    last = (clip / "data.csv").read_text(encoding="utf-8").strip().splitlines()[-1].split(",")
    assert abs(float(last[1]) - float(best["final_x"])) < 0.01
    assert abs(float(last[2]) - float(best["final_y"])) < 0.01
    published = (out / "sweeps/reach/results.jsonl").read_text(encoding="utf-8")
    assert published.count("\n") == 4 and "wall_seconds" not in published  # same bytes each build
    # built again: nothing runs (cached by the content of the inputs), the same bytes
    before = (out / "sweeps/reach/results.csv").read_bytes()
    lines.clear()
    build(BuildOptions(source=source, output=out, strict=True, log=lines.append))
    assert not [x for x in lines if x.startswith("sweep reach")]
    assert (out / "sweeps/reach/results.csv").read_bytes() == before


def test_a_sweep_that_cannot_run_is_a_warning_and_a_page_saying_why(tmp_path):
    source = write_tree(
        tmp_path / "src",
        {"sitegen.yml": CONFIG.replace("reach.py", "gone.py"), "content/index.md": "# H\n"},
    )
    out = tmp_path / "site"
    report = build(BuildOptions(source=source, output=out, log=lambda _line: None))
    assert [str(d) for d in report.diagnostics] == [
        "sitegen.yml: warning: sims.sweeps[0]: reach: gone.py: no such script file"
    ]
    assert "gone.py: no such script file" in (out / "gallery" / "reach.html").read_text()


@pytest.mark.parametrize(
    ("item", "message"),
    [
        ("{name: Up, script: a.py, scene: 2w1a, seeds: 0:3}", "sims.sweeps[0].name: must be"),
        ("{name: a, script: a.py, scene: 2w1a}", "sims.sweeps[0]: give seeds, grid or args"),
        ("{name: a, script: a.py, scene: 2w1a, seeds: x}", "sims.sweeps[0].seeds: 'x': give"),
        ("{name: a, script: a.py, scene: 2w1a, grid: {1x: [1]}}", "sims.sweeps[0].grid: '1x'"),
        ("{name: a, script: a.py, scene: 2w1a, seeds: '1', order: up}", "order: must be max"),
    ],
)
def test_bad_sweep_settings_name_line_and_key(item, message):
    text = f"sims:\n  executor: local\n  sweeps:\n    - {item}\n"
    with pytest.raises(BuildError) as bad:
        parse_config(text, Path("."))
    (only,) = bad.value.diagnostics
    assert str(only).startswith("sitegen.yml:4: error: ") and message in str(only)
    with pytest.raises(BuildError) as bad:
        parse_config("sims:\n  executor: dask\n", Path("."))
    assert [str(d) for d in bad.value.diagnostics] == [
        "sitegen.yml:2: error: sims.executor: must be one of local, ray"
    ]
