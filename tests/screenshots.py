"""Make docs/screenshots/*.png from the repository's own site: ``python3 tests/screenshots.py``.

Home, a week page, search as you type and the gallery, at 1280×800 (light) and 390×844 (dark),
in Debian's Chromium. PNGs are stored with fewer colour levels (flat UI colours survive, the
files stay small); the build uses the clip cache, so clips are rendered only on a first run.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from browser_kit import PHONE, WIDE, chromium, open_page, static_server  # noqa: E402
from sitegen_helpers import REPO, run_build  # noqa: E402

OUT = REPO / "docs" / "screenshots"
WEEK = "stage-1/w3/index.html"
SHOTS = [
    ("home", "index.html", None),
    ("week", WEEK, None),
    ("search", WEEK, "search"),
    ("gallery", "gallery/index.html", None),
]


def small_png(png: bytes, path: Path) -> None:
    image = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    # 32 levels a channel, rounded: UI colours stay true, deflate does much better
    image = np.minimum((image.astype(np.uint16) + 4) // 8 * 8, 255).astype(np.uint8)
    cv2.imwrite(str(path), image, [cv2.IMWRITE_PNG_COMPRESSION, 9])


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="sitegen-shots-") as tmp:
        site = Path(tmp) / "site"
        run_build(REPO, site)
        with chromium() as browser, static_server(site) as base:
            for size_name, size, scheme in (("wide", WIDE, "light"), ("phone", PHONE, "dark")):
                for name, rel, action in SHOTS:
                    with open_page(browser, size, site, scheme=scheme) as page:
                        page.goto(base + rel)
                        if action == "search":
                            page.keyboard.press("/")
                            page.keyboard.type("齒輪")
                            page.locator("#search-panel a").first.wait_for()
                            page.keyboard.press("ArrowDown")
                        page.wait_for_timeout(400)
                        path = OUT / f"{name}-{size_name}.png"
                        small_png(page.screenshot(), path)
                        print(f"{path.relative_to(REPO)}: {path.stat().st_size // 1024} KB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
