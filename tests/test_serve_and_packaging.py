"""``sitegen serve`` on loopback with rebuild and reload; the wheel carries the theme."""

from __future__ import annotations

import re
import subprocess
import sys
import time
import urllib.request
import zipfile

from sitegen_helpers import REPO, write_tree


def _get(url: str) -> str:
    with urllib.request.urlopen(url, timeout=10) as r:  # loopback only
        return r.read().decode()


def test_serve_rebuilds_on_change_and_signals_reload(tmp_path):
    src = write_tree(tmp_path / "s", {"index.md": "# Home\n\nfirst version\n"})
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "sitegen",
            "serve",
            "--source",
            str(src),
            "--output",
            str(tmp_path / "o"),
            "--port",
            "0",
        ],
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        port = None
        deadline = time.time() + 60
        while port is None and time.time() < deadline:
            line = proc.stderr.readline()
            m = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
            if m:
                port = int(m.group(1))
        assert port, "server did not report its address"
        base = f"http://127.0.0.1:{port}/"
        page = _get(base + "index.html")
        assert "first version" in page and "/__sitegen__/version" in page
        v0 = _get(base + "__sitegen__/version")
        (src / "index.md").write_text("# Home\n\nsecond version\n", encoding="utf-8")
        for _ in range(100):
            time.sleep(0.2)
            if _get(base + "__sitegen__/version") != v0:
                break
        assert "second version" in _get(base + "index.html")
        # the files on disk are a plain build: no reload script in them
        assert "__sitegen__" not in (tmp_path / "o/index.html").read_text(encoding="utf-8")
    finally:
        proc.terminate()
        proc.wait(timeout=10)


def test_wheel_contains_theme_and_all_packages(tmp_path):
    result = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-w", str(tmp_path), str(REPO)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr[-2000:]
    wheel = next(tmp_path.glob("*.whl"))
    names = set(zipfile.ZipFile(wheel).namelist())
    for needed in (
        "sitegen/_theme/base.html",
        "sitegen/_theme/assets/search.js",
        "sitegen/_theme/assets/favicon.svg",
        "sitegen/_theme/nav.js",
        "sitegen/_theme/menu.html",
        "sitegen/_theme/redirect.html",
        "sitegen/_theme/partials/clip.html",
        "sitegen/_theme/partials/gallery.html",
        "sitegen/_theme/partials/roster.html",
        "sitegen/starter/sitegen.yml",
        "sitegen/starter/content/stage-1/w1/cart.svg",
        "sitegen/starter/github/workflows/pages.yml",
        "sitegen/starter/scripts/drive.py",
        "sitegen/starter/scenes/rover.simscene.xml",
        "sitegen/starter/data/groups.txt",
        "sitegen/cli.py",
        "roster/__init__.py",
        "sims/world.py",
    ):
        assert needed in names, needed
    on_disk = {
        p.parent.relative_to(REPO).as_posix()
        for p in REPO.glob("*/**/__init__.py")
        if p.parts[len(REPO.parts)] in ("sitegen", "roster", "sims")
    }
    in_wheel = {n.rsplit("/", 1)[0] for n in names if n.endswith("__init__.py")}
    assert on_disk <= in_wheel, f"packages missing from pyproject: {sorted(on_disk - in_wheel)}"
    # the licence pyproject names travels with the wheel
    assert any(n.endswith(".dist-info/licenses/LICENSE") or n.endswith("/LICENSE") for n in names)
    assert "MIT License" in (REPO / "LICENSE").read_text(encoding="utf-8")
