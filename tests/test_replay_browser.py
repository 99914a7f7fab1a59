"""Replays in a real browser: Debian's Chromium (WebGL 2 through SwiftShader) on this
repository's own site, over http (as GitHub Pages serves it) and from file://, wide and phone.

For every replay of the gallery: the viewer loads, its animation lasts as long as the run,
the robot is drawn (its screen region changes when its moving links are hidden), two times
show two poses that match the recorded ones (data.csv), orbiting changes the view, no
console error, no request outside the site. Also: the controls and keys, reduced motion
(poster, no autoplay), no WebGL (poster and a note), the viewer's script only on pages with a
replay, and readable plots in dark mode.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re

import numpy as np
import pytest
from browser_kit import PHONE, WIDE, chromium, open_page, require_browser, static_server
from sitegen_helpers import REPO, run_build

READY = "f => ['ready', 'failed', 'no-webgl'].includes(f.dataset.state)"


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    require_browser()
    out = tmp_path_factory.mktemp("replay") / "site"
    run_build(REPO, out)
    return out


@pytest.fixture(scope="module")
def browser(site):
    with chromium() as b:
        yield b


@pytest.fixture(scope="module")
def http_url(site):
    with static_server(site) as url:
        yield url


def clips_of(site) -> list[str]:
    html = (site / "gallery" / "index.html").read_text(encoding="utf-8")
    return re.findall(r'<figure class="clip clip-replay" id="clip-([^"]+)"', html)


def recorded(site, name: str) -> tuple[str, list[dict[str, float]], dict]:
    data = json.loads((site / "clips" / name / "data.json").read_text(encoding="utf-8"))
    text = (site / "clips" / name / "data.csv").read_text(encoding="utf-8")
    rows = [
        {k: float(v) for k, v in r.items() if v != ""} for r in csv.DictReader(io.StringIO(text))
    ]
    return data["subject"], rows, data


def euler_matrix(alpha: float, beta: float, gamma: float) -> np.ndarray:
    """CoppeliaSim's Euler angles (degrees): R = Rx(alpha) Ry(beta) Rz(gamma)."""
    a, b, c = (math.radians(v) for v in (alpha, beta, gamma))
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rx @ ry @ rz


def quat_matrix(q: list[float]) -> np.ndarray:
    x, y, z, w = np.asarray(q, dtype=np.float64) / np.linalg.norm(q)  # float32 in the browser
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def angle_between(a: np.ndarray, b: np.ndarray) -> float:
    cos = (np.trace(a.T @ b) - 1) / 2
    return math.degrees(math.acos(max(-1.0, min(1.0, cos))))


def shot(page, fig) -> np.ndarray:
    import cv2

    png = fig.locator("canvas").screenshot()
    return cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR).astype(np.int16)


def ready(page, name: str):
    fig = page.locator(f"#clip-{name}")
    fig.scroll_into_view_if_needed()
    fig.evaluate(
        f"f => new Promise(done => {{ const t = setInterval(() => {{ if (({READY})(f)) "
        "{ clearInterval(t); done(); } }, 50); })"
    )
    assert fig.evaluate("f => f.dataset.state") == "ready", name
    fig.evaluate("f => f.sitegenReplay.pause()")
    return fig


@pytest.mark.parametrize(
    "where,size", [("http", WIDE), ("file", PHONE)], ids=["http-wide", "file-phone"]
)
def test_every_replay_draws_the_robot_and_follows_the_tape(site, browser, http_url, where, size):
    names = clips_of(site)
    assert len(names) >= 9  # this repository's site: every clip is a replay
    base = http_url if where == "http" else site.resolve().as_uri() + "/"
    with open_page(browser, size, site) as page:
        page.goto(base + "gallery/index.html")
        for name in names:
            subject, rows, data = recorded(site, name)
            fig = ready(page, name)
            api = "f => f.sitegenReplay"
            duration = len(rows) / data["fps"]
            assert fig.evaluate(api + ".clipDuration") == pytest.approx(duration, abs=1e-3)
            assert fig.evaluate(api + ".duration") == pytest.approx(duration, abs=1e-3)
            shots, poses = [], []
            for share in (0.3, 0.8):
                row = rows[int(share * (len(rows) - 1))]
                fig.evaluate(f"f => f.sitegenReplay.seek({row['t']})")
                pose = fig.evaluate(f"f => f.sitegenReplay.pose({json.dumps(subject)})")
                assert pose is not None, f"{name}: no node {subject}"
                where_at = np.array(pose["position"])
                assert np.linalg.norm(where_at - [row["x"], row["y"], row["z"]]) < 0.003, name
                turn = euler_matrix(row["alpha_deg"], row["beta_deg"], row["gamma_deg"])
                assert angle_between(quat_matrix(pose["quaternion"]), turn) < 0.6, name
                poses.append(pose)
                shots.append(shot(page, fig))
            moved = np.abs(shots[0] - shots[1]).max(axis=2) > 24
            assert moved.sum() > 30, f"{name}: the two times look the same"
            # the robot is drawn: hiding it changes the pixels around its place on screen
            x, y = fig.evaluate(f"f => f.sitegenReplay.screen({json.dumps(subject)})")
            box = fig.locator("canvas").bounding_box()
            cx, cy = int(x - box["x"]), int(y - box["y"])
            robot = "f => f.sitegenReplay.moving.forEach(n => f.sitegenReplay.show(n, %s))"
            fig.evaluate(robot % "false")
            hidden = shot(page, fig)
            fig.evaluate(robot % "true")
            h, w = hidden.shape[:2]
            region = (
                slice(max(0, cy - 30), min(h, cy + 30)),
                slice(max(0, cx - 30), min(w, cx + 30)),
            )
            drawn = np.abs(shots[1][region] - hidden[region]).max(axis=2) > 12
            assert drawn.sum() > 20, f"{name}: the robot is not drawn where it is"
            fig.evaluate("f => f.sitegenReplay.orbit(0.7)")
            orbited = shot(page, fig)
            assert (np.abs(orbited - shots[1]).max(axis=2) > 24).sum() > 200, name


def test_controls_and_keys(site, browser, http_url):
    with open_page(browser, WIDE, site) as page:
        page.goto(http_url + "gallery/index.html")
        fig = ready(page, "2w1a-random")
        bar = fig.locator(".replay-bar")
        assert bar.is_visible()
        fig.evaluate("f => f.sitegenReplay.seek(0)")
        assert fig.locator(".replay-clock").inner_text() == "0.0 / 75.0 秒"
        stage = fig.locator(".replay-stage")
        stage.focus()
        page.keyboard.press("Space")
        assert fig.evaluate("f => f.sitegenReplay.playing")
        assert fig.locator(".replay-play").get_attribute("aria-label") == "暫停"
        page.wait_for_timeout(400)
        page.keyboard.press("Space")
        t = fig.evaluate("f => f.sitegenReplay.time")
        assert t > 0.5  # played at 8x: the clip's own speed, selected
        assert fig.locator(".replay-speed").input_value() == "8"
        page.keyboard.press("ArrowRight")
        assert fig.evaluate("f => f.sitegenReplay.time") == pytest.approx(t + 1, abs=1e-6)
        page.keyboard.press("End")
        assert fig.evaluate("f => f.sitegenReplay.time") == pytest.approx(75.0)
        cursor = fig.locator(".plot-cursor")
        assert float(cursor.get_attribute("x1")) == pytest.approx(388.0, abs=0.2)  # plot's end
        fig.locator(".replay-time").evaluate(
            "i => { i.value = '10'; i.dispatchEvent(new Event('input', {bubbles: true})); }"
        )
        assert fig.evaluate("f => f.sitegenReplay.time") == pytest.approx(10.0)
        assert fig.locator(".replay-clock").inner_text() == "10.0 / 75.0 秒"
        options = fig.locator(".replay-speed option").all_inner_texts()
        assert options == ["0.25×", "0.5×", "1×", "2×", "4×", "8×"]
        before = shot(page, fig)
        fig.evaluate("f => f.sitegenReplay.orbit(1.0)")
        fig.locator(".replay-reset").click()
        assert (np.abs(shot(page, fig) - before).max(axis=2) > 24).sum() < 50  # the start view


def test_reduced_motion_shows_the_poster_until_play(site, browser, http_url):
    context = browser.new_context(viewport=WIDE, reduced_motion="reduce")
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    try:
        page.goto(http_url + "gallery/index.html")
        fig = page.locator("#clip-2w1a-random")
        page.wait_for_timeout(800)
        assert fig.evaluate("f => f.dataset.state") == "poster"  # no autoplay, nothing loaded
        assert fig.locator("img.replay-poster").is_visible()
        assert page.evaluate("() => !window.SITEGEN_THREE")
        fig.locator(".replay-play").click()
        fig.evaluate(
            f"f => new Promise(d => {{ const t = setInterval(() => {{ if (({READY})(f)) "
            "{ clearInterval(t); d(); } }, 50); })"
        )
        assert fig.evaluate("f => f.dataset.state") == "ready"
        assert fig.evaluate("f => f.sitegenReplay.playing")
        assert errors == []
    finally:
        context.close()


def test_without_webgl_the_poster_stays(site, browser, http_url):
    from browser_kit import ARGS, CHROMIUM

    bare = browser.browser_type.launch(executable_path=CHROMIUM, args=[*ARGS, "--disable-3d-apis"])
    try:
        with open_page(bare, WIDE, site) as page:
            page.goto(http_url + "gallery/index.html")
            fig = page.locator("#clip-2w1a-random")
            page.wait_for_function(
                "() => document.querySelector('#clip-2w1a-random').dataset.state === 'no-webgl'"
            )
            assert fig.locator("img.replay-poster").is_visible()
            assert fig.locator(".replay-note").is_visible()
            assert "WebGL" in fig.locator(".replay-note").inner_text()
            assert not fig.locator(".replay-bar").is_visible()
    finally:
        bare.close()


def test_the_viewer_loads_only_on_pages_with_a_replay(site, browser, http_url):
    with_replay, without = 0, 0
    for page in site.rglob("*.html"):
        html = page.read_text(encoding="utf-8")
        if "clip-replay" in html:
            with_replay += 1
            assert html.count('assets/replay/replay.js" defer></script>') == 1, page
        else:
            without += 1
            assert "assets/replay/" not in html, page
    assert with_replay >= 6 and without > 20
    seen: list[str] = []
    with open_page(browser, WIDE, site) as page:
        page.on("request", lambda r: seen.append(r.url))
        page.goto(http_url + "index.html")
        page.wait_for_load_state("load")
        assert not any("assets/replay/" in url for url in seen)


def test_plots_are_themed_and_readable(site, browser, http_url):
    with open_page(browser, PHONE, site, scheme="dark") as page:
        page.goto(http_url + "gallery/index.html")
        plots = page.locator(".gallery-item .plot svg")
        assert plots.count() >= 9
        for i in range(plots.count()):
            svg = plots.nth(i)
            fill = svg.locator("rect").first.evaluate("r => getComputedStyle(r).fill")
            rgb = [int(v) for v in re.findall(r"\d+", fill)[:3]]
            assert sum(rgb) < 3 * 60, f"plot {i} is not dark: {fill}"
            size = svg.evaluate(
                "s => s.getScreenCTM().a"
                " * parseFloat(getComputedStyle(s.querySelector('text')).fontSize)"
            )
            assert size >= 11, f"plot {i}: {size:.1f} px labels"
