"""The project's own remote API scripts behind the site's clips do the experiment they describe.

``sitegen.yml`` names only files in the repository: these scripts replace the course scripts the
site once ran from ``../shared`` (which stay test data, tests/test_remote_api_scripts.py).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import yaml

from sims.remote_api.runner import run_script

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples" / "remote_api"


def test_the_site_config_names_only_files_inside_the_repository():
    config = yaml.safe_load((REPO / "sitegen.yml").read_text(encoding="utf-8"))
    for clip in config["sims"]["clips"]:
        for key in ("script", "scene"):
            value = clip.get(key)
            if value and ("/" in value or value.endswith((".py", ".xml", ".ttt", ".json"))):
                path = (REPO / value).resolve()
                assert path.is_file() and REPO in path.parents, (clip["name"], value)
                assert "shared" not in Path(value).parts


def test_arm_random_moves_runs_two_simulations_of_five_random_poses(capsys):
    result = run_script(EXAMPLES / "arm_random_moves.py", "2w1a", seed=2021)
    out = capsys.readouterr().out
    assert result.exit_code == 0, result.message
    assert result.simulations == 2 and 40 <= result.sim_time <= 44
    moves = re.findall(r"move \d: ShoulderMotor (\d+)->(\d+), ElbowMotor (\d+)->(\d+)", out)
    assert len(moves) == 10
    targets = {(int(s), int(e)) for s, _, e, _ in moves}
    assert len(targets) == 10  # random, not one pose repeated
    errors = [abs(int(a) - int(b)) for s, sr, e, er in moves for a, b in ((s, sr), (e, er))]
    assert sorted(errors)[len(errors) // 2] <= 3  # the arm mostly gets there within 4 s
    again = run_script(EXAMPLES / "arm_random_moves.py", "2w1a", seed=2021)
    assert capsys.readouterr().out == out and again.ok  # the clip's seed makes it reproducible


def test_cart_velocity_goes_forward_turns_and_backs_up(capsys):
    result = run_script(EXAMPLES / "cart_velocity.py", "cart", seed=0, after=1.0)
    out = capsys.readouterr().out
    assert result.exit_code == 0, result.message
    xy = {
        what: (float(x), float(y))
        for what, x, y in re.findall(r"(\w+): cart at x=(\S+) y=(\S+) m", out)
    }
    assert list(xy) == ["forward", "turn", "backwards", "stopped"]
    assert xy["forward"][0] > 0.08  # 3 s at 1.5 rad/s on 28 mm wheels: about 12 cm
    turned = math.dist(xy["forward"], xy["turn"])
    assert turned < 0.03  # turning on the spot
    assert math.dist(xy["turn"], xy["backwards"]) > 0.08
    assert xy["backwards"] == xy["stopped"]
