"""``BuildOptions(render_clips=False)``: a build that renders no clip (``sitegen serve``'s first).

Cached clips are shown, the others get a "rendering…" placeholder with no warning, and the next
full build is not skipped as up to date: it renders them and the pages show the replays.
"""

from __future__ import annotations

from sitegen_helpers import write_tree

from sitegen.build import BuildOptions, build

CONFIG = """title: t
sims:
  size: 64x48
  fps: 4
  clips:
    - {name: one, scenario: cart-reverse, seconds: 1}
    - {name: two, scenario: cart-reverse, seconds: 2}
"""


def test_a_quick_build_shows_placeholders_then_the_full_build_renders(tmp_path):
    source = write_tree(
        tmp_path / "src",
        {"sitegen.yml": CONFIG, "content/index.md": "# Home\n\n::: clip one\n\n::: clip two\n"},
    )
    out = tmp_path / "site"
    lines: list[str] = []

    def run(**kw):
        opts = BuildOptions(source=source, output=out, strict=True, log=lines.append, **kw)
        return build(opts), (out / "index.html").read_text(encoding="utf-8")

    report, home = run(render_clips=False)
    assert [str(d) for d in report.diagnostics] == []
    assert home.count('class="clip clip-pending"') == 2 and "rendering…" in home
    assert "clip-replay" not in home and not (out / "clips").exists()
    assert not any("started" in line for line in lines)

    report, home = run()
    assert [str(d) for d in report.diagnostics] == [] and not report.up_to_date
    assert home.count('class="clip clip-replay"') == 2 and "clip-pending" not in home
    assert (out / "clips" / "two" / "replay.glb").is_file()

    lines.clear()
    write_tree(source, {"sitegen.yml": CONFIG.replace("seconds: 2", "seconds: 1.5")})
    report, home = run(render_clips=False)  # one clip changed: its last good render meanwhile
    assert [str(d) for d in report.diagnostics] == []
    assert home.count('class="clip clip-replay"') == 2 and "clip-pending" not in home
    assert not any("started" in line for line in lines)
    report, home = run()
    assert any("clip two: started" in line for line in lines)
    assert home.count('class="clip clip-replay"') == 2
