"""Rosters and simulation clips inside a built site."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest
from shared_data import shared
from sitegen_helpers import run_build, run_cli, write_tree

from sitegen.check import check_site
from sitegen.errors import BuildError

ROSTER_CFG = """title: t
course_repo: cd2021
rosters:
  - {name: stage3-2a, title: Stage 3 groups, file: data/roster.txt,
     corrections: data/fix.yml, section: stage-3/grouping}
"""
FIX = 'aliases:\n  "40823112": "a40823112"\ngroup_names:\n  - {replace: "_", with: "-"}\n'


@pytest.fixture()
def roster_project(tmp_path: Path) -> Path:
    return write_tree(
        tmp_path / "p",
        {
            "sitegen.yml": ROSTER_CFG,
            "data/roster.txt": shared("data", "stage3_2a.txt").read_text(encoding="utf-8"),
            "data/fix.yml": FIX,
            "content/index.md": "# Home\n",
            "content/stage-3/grouping/index.md": "# Stage 3 分組\n",
            "content/stage-3/w12/task1.md": "# Task 1\n\n::: roster stage3-2a\n",
        },
    )


def test_roster_page_lists_every_group_with_anchors_and_json(roster_project, tmp_path):
    out = tmp_path / "o"
    run_build(roster_project, out)
    page = (out / "stage-3/grouping/stage-3-groups.html").read_text(encoding="utf-8")
    data = json.loads((out / "roster/stage3-2a.json").read_text(encoding="utf-8"))
    assert len(data["groups"]) == 6
    for group in data["groups"]:
        assert f'id="group-{group["slug"]}"' in page
        assert f'href="#group-{group["slug"]}"' in page  # on-page table of contents
        assert group["repo_url"] in page
    assert "https://github.com/a40823112/cd2021" in page
    assert 'href="../../roster/stage3-2a.json"' in page
    embedded = (out / "stage-3/w12/task-1.html").read_text(encoding="utf-8")
    assert "https://a40823112.github.io/cd2021" in embedded
    assert check_site(out) == []


def test_roster_edit_is_reported_on_rebuild(roster_project, tmp_path):
    out = tmp_path / "o"
    run_build(roster_project, out)
    path = roster_project / "data/roster.txt"
    lines = path.read_text(encoding="utf-8").split("\n")
    lines[0] = lines[0].replace("\t40823108\t40823108", "")  # remove from ag1
    lines[1] = lines[1] + "\t40823108\t40823108"  # ... add to ag2
    path.write_text("\n".join(lines), encoding="utf-8")
    report = run_build(roster_project, out)
    assert any("40823108" in n and "moved" in n for n in report.notes), report.notes


def test_unsafe_account_fails_the_build_with_file_and_line(roster_project, tmp_path):
    out = tmp_path / "o"
    run_build(roster_project, out)
    before = (out / "roster/stage3-2a.json").read_bytes()
    path = roster_project / "data/roster.txt"
    text = path.read_text(encoding="utf-8").replace(
        "\t40823151\t40823151", "\t40823151\tjavascript:alert(1)"
    )
    path.write_text(text, encoding="utf-8")
    result = run_cli("build", "--source", str(roster_project), "--output", str(out))
    assert result.returncode == 1
    assert re.search(r"data/roster\.txt:2: .*account", result.stderr), result.stderr
    assert "Traceback" not in result.stderr
    assert (out / "roster/stage3-2a.json").read_bytes() == before


SIMS_CFG = """title: t
sims:
  size: 96x64
  fps: 8
  formats: [video]
  clips:
    - {name: rev, scenario: cart-reverse, seconds: 1.5}
"""


@pytest.fixture(scope="module")
def sims_site(tmp_path_factory) -> tuple[Path, Path]:
    root = tmp_path_factory.mktemp("sims")
    src = write_tree(
        root / "p", {"sitegen.yml": SIMS_CFG, "content/index.md": "# Home\n\n::: clip rev\n"}
    )
    out = root / "o"
    run_build(src, out)
    return src, out


def test_clip_directive_embeds_a_browser_friendly_video(sims_site):
    _src, out = sims_site
    page = (out / "index.html").read_text(encoding="utf-8")
    video = re.search(r"<video[^>]*>", page).group(0)
    for attr in (
        "controls",
        "muted",
        "playsinline",
        'preload="metadata"',
        'poster="clips/rev/poster.png"',
    ):
        assert attr in video
    assert '<source src="clips/rev/clip.webm" type="video/webm; codecs=vp8">' in page
    for name in ("clip.webm", "poster.png", "data.csv", "data.json", "path.svg"):
        assert (out / "clips/rev" / name).stat().st_size > 0
    gallery = (out / "gallery/index.html").read_text(encoding="utf-8")
    assert 'id="clip-rev"' in gallery and "data.csv" in gallery and 'class="plot-svg"' in gallery
    assert "cart_reverse.py" in gallery  # the scenario's source is shown
    assert check_site(out) == []


def test_failed_clip_is_named_keeps_previous_render_and_fails_strict(sims_site, tmp_path):
    src, out = sims_site
    proj = tmp_path / "p"
    shutil.copytree(src, proj)
    cfg = proj / "sitegen.yml"
    cfg.write_text(SIMS_CFG.replace("cart-reverse", "no-such-scenario"), encoding="utf-8")
    result = run_cli("build", "--source", str(proj), "--output", str(out))
    assert result.returncode == 0
    assert "sims.clips[rev]" in result.stderr and "no-such-scenario" in result.stderr
    assert (out / "clips/rev/clip.webm").exists()  # the previous render is still published
    with pytest.raises(BuildError):
        run_build(proj, tmp_path / "strict", strict=True)


def test_unknown_clip_name_in_a_page_is_an_error_with_line(tmp_path):
    src = write_tree(
        tmp_path / "p",
        {
            "sitegen.yml": SIMS_CFG.replace(
                "clips:\n    - {name: rev, scenario: cart-reverse, seconds: 1.5}\n", "clips: []\n"
            ),
            "content/index.md": "# Home\n\ntext\n\n::: clip nope\n",
        },
    )
    with pytest.raises(BuildError) as info:
        run_build(src, tmp_path / "o")
    assert any(d.line == 5 and "no clip named 'nope'" in d.message for d in info.value.diagnostics)
