"""Clip keys ``camera: follow|overview`` and ``trail: true`` (slow motion made visible).

``overview`` films the whole clip from one fixed camera framing the followed object's whole
path; ``trail`` draws the path travelled so far on the floor. Both reach the render from
sitegen.yml, are part of the clip's cache key, and leave the keys of plain clips unchanged.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from sitegen_helpers import write_tree

from sims.clips import ClipSpec, spec_fields
from sitegen.build import BuildOptions, build
from sitegen.config import parse_config
from sitegen.errors import BuildError

CONFIG = """title: t
sims:
  formats: [video]
  size: 128x96
  fps: 8
  clips:
    - {name: plain, scenario: cart-avoid, seconds: 6, speed: 2}
    - {name: above, scenario: cart-avoid, seconds: 6, speed: 2, camera: overview, trail: true}
    - {name: chase, scenario: cart-avoid, seconds: 6, speed: 2, trail: true}
"""


def orange(path) -> int:
    """Pixels of the trail's colour (255, 96, 0, anti-aliased) in a PNG."""
    rgb = cv2.cvtColor(cv2.imread(str(path)), cv2.COLOR_BGR2RGB).astype(int)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return int(((r > 200) & (g > 50) & (g < 150) & (b < 80)).sum())


def test_the_keys_are_read_from_sitegen_yml_and_checked(tmp_path):
    clips = parse_config(CONFIG, tmp_path).sims.clips
    assert [(c.camera, c.trail) for c in clips] == [
        ("follow", False),
        ("overview", True),
        ("follow", True),
    ]
    with pytest.raises(BuildError) as info:
        parse_config(
            "sims:\n  clips:\n    - {name: a, scenario: cart-avoid, camera: top}\n", tmp_path
        )
    assert [(d.line, d.field, d.message) for d in info.value.diagnostics] == [
        (3, "sims.clips[0].camera", "must be follow or overview")
    ]
    with pytest.raises(BuildError) as info:
        parse_config("sims:\n  clips:\n    - {name: a, scenario: cart-avoid, trail: 1}\n", tmp_path)
    assert info.value.diagnostics[0].field == "sims.clips[0].trail"


def test_camera_and_trail_are_part_of_the_cache_key_and_plain_keys_stay():
    def fields(**kw):
        return spec_fields(ClipSpec(name="a", scenario="cart-avoid", **kw), 0, {})

    plain = fields()
    assert "camera" not in plain and "trail" not in plain  # existing caches stay valid
    assert fields(camera="follow", trail=False) == plain
    variants = [
        plain,
        fields(camera="overview"),
        fields(trail=True),
        fields(camera="overview", trail=True),
    ]
    assert len({repr(sorted(v.items())) for v in variants}) == 4


def test_overview_and_trail_reach_the_rendered_frames(tmp_path):
    source = write_tree(
        tmp_path / "src",
        {"sitegen.yml": CONFIG, "content/index.md": "# Home\n\n::: clip above\n"},
    )
    out = tmp_path / "site"
    report = build(BuildOptions(source=source, output=out, strict=True, log=lambda line: None))
    assert [str(d) for d in report.diagnostics] == []
    posters = {n: out / "clips" / n / "poster.png" for n in ("plain", "above", "chase")}
    assert orange(posters["plain"]) == 0
    assert orange(posters["above"]) > 40 and orange(posters["chase"]) > 40
    frames = {n: cv2.imread(str(p)).astype(int) for n, p in posters.items()}
    # the chase camera frames the same scene the same way with or without the trail
    same = np.all(frames["plain"] == frames["chase"], axis=2).mean()
    assert same > 0.9
    assert np.all(frames["plain"] == frames["above"], axis=2).mean() < 0.5  # another camera
