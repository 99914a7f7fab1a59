"""Lighthouse's accessibility score of a new site's pages, light and dark, phone and desktop.

Run: ``npm ci --prefix bench/a11y && python bench/a11y_bench.py`` (Lighthouse 12 from npm, the
last major that runs on Node 18-20; Debian's Chromium). The site is the one the accessibility
test checks with axe-core (tests/reader_site.py: ``sitegen new`` plus a deck, blog posts and the
pages the reader tests need), served on 127.0.0.1. Lighthouse is a bench, not a test: it takes
10-20 s a page and 185 MB of npm packages, where the test (tests/test_accessibility.py) runs
axe-core, the engine of Lighthouse's accessibility audits, on the same pages in seconds.

Prints one line per page, scheme and form factor with the score and any failed audit; exits 1
if any score is below 100.
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import subprocess
import sys
import tempfile
import threading
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

from reader_site import build_reader_site  # noqa: E402

PAGES = {
    "week page": "stage-1/w1/index.html",
    "gallery": "gallery/index.html",
    "deck": "slides/w1-report.slides.html",
    "blog index": "blog/index.html",
}


class _Quiet(SimpleHTTPRequestHandler):
    def log_message(self, *args) -> None:
        pass


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--site", type=Path, help="a built site to audit instead of a new one")
    args = parser.parse_args()
    runner = HERE / "a11y" / "lighthouse_one.mjs"
    if not (HERE / "a11y" / "node_modules" / "lighthouse").is_dir():
        print("bench/a11y_bench.py: run `npm ci --prefix bench/a11y` first", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory(prefix="a11y-bench-") as tmp:
        site = args.site or build_reader_site(Path(tmp) / "course") / "site"
        handler = functools.partial(_Quiet, directory=str(site))
        server = ThreadingHTTPServer(("127.0.0.1", 0), handler)
        threading.Thread(target=server.serve_forever, daemon=True).start()
        base = f"http://127.0.0.1:{server.server_address[1]}/"
        worst = 100
        try:
            for name, rel in PAGES.items():
                for scheme in ("light", "dark"):
                    for form in ("mobile", "desktop"):
                        done = subprocess.run(
                            ["node", str(runner), base + rel, scheme, form],
                            capture_output=True,
                            text=True,
                            timeout=300,
                            env={**os.environ, "CHROME_PATH": "/usr/bin/chromium"},
                        )
                        if done.returncode != 0:
                            why = done.stderr[-400:]
                            print(f"{name} {scheme} {form}: lighthouse failed: {why}")
                            worst = 0
                            continue
                        r = json.loads(done.stdout.strip().splitlines()[-1])
                        worst = min(worst, r["score"])
                        failed = ", ".join(r["failed"]) or "-"
                        print(
                            f"{name:11} {scheme:5} {form:7} accessibility {r['score']:3}  "
                            f"failed: {failed}  (page saw {r['seen'][0]}, body {r['seen'][1]})",
                            flush=True,
                        )
        finally:
            server.shutdown()
    return 0 if worst == 100 else 1


if __name__ == "__main__":
    raise SystemExit(main())
