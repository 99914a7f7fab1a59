"""What the reader-side browser tests share: Chromium, a loopback server, a request watch.

Pages are opened over http (a plain static server on 127.0.0.1, as GitHub Pages would serve
them) and from ``file://`` (a site opened from disk). Any request that leaves 127.0.0.1 or the
site folder is blocked and fails the test; so does any console error (a missing favicon or
script shows up as one).
"""

from __future__ import annotations

import contextlib
import functools
import os
import shutil
import threading
from collections.abc import Iterator
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from urllib.parse import urlsplit

import pytest

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--autoplay-policy=no-user-gesture-required",
]
WIDE = {"width": 1280, "height": 800}
PHONE = {"width": 390, "height": 844}
SIZES = {"wide": WIDE, "phone": PHONE}


def require_browser() -> None:
    missing = []
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        missing.append("playwright (pip install -e '.[test]')")
    if not os.path.exists(CHROMIUM):
        missing.append("chromium (apt-get install chromium)")
    if missing:
        message = "browser tests need " + ", ".join(missing)
        if os.environ.get("CI"):
            pytest.fail(message)
        pytest.skip(message)


class _Quiet(SimpleHTTPRequestHandler):
    def log_message(self, *args) -> None:
        pass


@contextlib.contextmanager
def static_server(folder: Path) -> Iterator[str]:
    """Serve ``folder`` on 127.0.0.1; yields the base URL ending in '/'."""
    server = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(folder)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()


@contextlib.contextmanager
def chromium() -> Iterator:
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS, headless=True)
        try:
            yield browser
        finally:
            browser.close()


class Watch:
    """Console errors, failed responses, and blocked requests that leave the site."""

    def __init__(self, page, site: Path | None = None):
        self.errors: list[str] = []
        self.outside: list[str] = []
        self.site = str(site.resolve()) if site else None
        page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: self.errors.append(str(e)))
        page.route("**/*", self._route)

    def _route(self, route) -> None:
        url = route.request.url
        parts = urlsplit(url)
        inside = url.startswith(("data:", "blob:")) or parts.hostname == "127.0.0.1"
        if parts.scheme == "file" and self.site:
            inside = os.path.realpath(parts.path).startswith(self.site)
        if inside:
            route.continue_()
        else:
            self.outside.append(url)
            route.abort()

    def check(self) -> None:
        assert self.outside == [], f"requests left the site: {self.outside}"
        assert self.errors == [], f"console errors: {self.errors}"


@contextlib.contextmanager
def open_page(browser, size: dict, site: Path, scheme: str = "light", js: bool = True):
    """A fresh context (so localStorage starts empty) at ``size`` with a watch; checked on exit."""
    phone = size["width"] < 600
    context = browser.new_context(
        viewport=size,
        is_mobile=phone,
        has_touch=phone,
        color_scheme=scheme,
        java_script_enabled=js,
    )
    context.grant_permissions(["clipboard-read", "clipboard-write"])
    page = context.new_page()
    page.watch = Watch(page, site)
    try:
        yield page
        page.watch.check()
    finally:
        context.close()
