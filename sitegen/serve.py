"""``sitegen serve``: build, serve on loopback, rebuild on change, reload the open page.

The address is checked first (bound before anything is built), so a port in use or out of
range is one line and a non-zero exit, not a traceback after a long build. The server only
binds to a loopback address. Watching polls file stats twice a second (cheap for a course site,
no extra dependency); the build itself still decides what changed by content hash. Served HTML
gets a tiny script that polls ``/__sitegen__/version`` and reloads the page when a rebuild lands;
files on disk are never modified, so the built site stays byte-identical to ``sitegen build``.
A missing page is answered with the site's own 404 page (status 404), as GitHub Pages does.

When the build supports it (``BuildOptions.render_clips``), the first build publishes the site
with the clips already cached and the server starts at once; the clips are then rendered in
the background and the open page reloads when they are in.

Files answer single-range requests (``Range: bytes=A-B``: 206 with ``Content-Range``, 416 when
the range starts past the end; ``Accept-Ranges: bytes``), as Safari needs to play a video;
several ranges in one request get the whole file (200), which HTTP allows. The server keeps a
listen queue of ``BACKLOG`` connections and drops a client silent for ``REQUEST_TIMEOUT``
seconds, so many clients at once, or slow ones, do not lock others out. A request path that
cannot be a file name (a NUL byte) is a 404, like any other missing file.
"""

from __future__ import annotations

import argparse
import dataclasses
import errno
import functools
import io
import ipaddress
import os
import re
import sys
import threading
import time
from http import HTTPStatus
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

from sitegen.build import BuildOptions, build, resolve_paths
from sitegen.errors import BuildError
from sitegen.source_stats import snapshot

RELOAD_JS = b"""<script>(function(){var v=null;
function poll(){fetch("/__sitegen__/version",{cache:"no-store"})
.then(function(r){return r.text()}).then(function(t){if(v!==null&&t!==v){location.reload()}v=t})
.catch(function(){}).finally(function(){setTimeout(poll,1000)})}poll()})();</script>"""


class AddressError(ValueError):
    """A --dev-addr or --port the server cannot use; the message is one line for the user."""


def parse_dev_addr(text: str) -> tuple[str, int]:
    """``HOST:PORT`` (``[::1]:PORT`` for IPv6) -> (host, port); loopback hosts only."""
    host, sep, port_text = text.rpartition(":")
    if not sep or not host:
        raise AddressError(f"--dev-addr '{text}': expected HOST:PORT, e.g. 127.0.0.1:8000")
    host = host[1:-1] if host.startswith("[") and host.endswith("]") else host
    return check_host(host), check_port(port_text)


def check_port(text: str | int) -> int:
    try:
        port = int(text)
    except ValueError:
        raise AddressError(f"port '{text}' is not a number") from None
    if not 0 <= port <= 65535:
        raise AddressError(f"port {port} is out of range (0-65535; 0 picks a free one)")
    return port


def check_host(host: str) -> str:
    if host == "localhost":
        return "127.0.0.1"
    try:
        ip = ipaddress.ip_address(host)
    except ValueError:
        raise AddressError(f"host '{host}' is not an IP address (use 127.0.0.1 or ::1)") from None
    if not ip.is_loopback:
        raise AddressError(
            f"host '{host}' is not a loopback address: sitegen serves on this machine only"
        )
    return host


class _State:
    def __init__(self) -> None:
        self.version = 0
        self.lock = threading.Lock()
        self.failed = False  # the last build raised
        self.problems: set[str] = set()  # the last build's diagnostics, as printed


BACKLOG = 128  # connections waiting to be accepted (socketserver's default is 5)
REQUEST_TIMEOUT = 30.0  # seconds a client may stay silent in the middle of a request
RANGE = re.compile(r"^bytes=(\d*)-(\d*)$")


class _Server(ThreadingHTTPServer):
    daemon_threads = True
    request_queue_size = BACKLOG


def make_server(host: str, port: int, directory: Path, state: _State) -> ThreadingHTTPServer:
    """Bind now (before any build); raise :class:`AddressError` with a one-line reason."""
    server_class = _Server
    if ":" in host:
        import socket

        server_class = type("_Server6", (_Server,), {"address_family": socket.AF_INET6})
    handler = functools.partial(_Handler, directory=str(directory))
    _Handler.state = state
    try:
        return server_class((host, port), handler)
    except OverflowError:
        raise AddressError(f"port {port} is out of range (0-65535)") from None
    except OSError as exc:
        if exc.errno == errno.EADDRINUSE:
            raise AddressError(
                f"{host}:{port} is in use (another sitegen serve?): "
                f"pick another port with --dev-addr {host}:{port + 1 if port < 65535 else 8000}"
            ) from None
        if exc.errno in (errno.EACCES, errno.EPERM):
            raise AddressError(
                f"{host}:{port}: permission denied (ports below 1024 need root)"
            ) from None
        raise AddressError(f"cannot listen on {host}:{port}: {exc.strerror or exc}") from None


class _Handler(SimpleHTTPRequestHandler):
    state: _State
    timeout = REQUEST_TIMEOUT

    def log_message(self, format: str, *args) -> None:  # noqa: A002 (http.server's name)
        pass

    def translate_path(self, path: str) -> str:
        """Nothing is served through a symlink that leads out of the site, nor for a path no
        file can have (a NUL byte): 404 instead."""
        nowhere = os.path.join(os.path.realpath(self.directory), "__sitegen__", "outside-the-site")
        fs_path = super().translate_path(path)
        if "\0" in fs_path:
            return nowhere  # never exists
        root = os.path.realpath(self.directory)
        real = os.path.realpath(fs_path)
        if real != root and not real.startswith(root.rstrip(os.sep) + os.sep):
            return nowhere
        return fs_path

    def send_head(self):  # noqa: ANN201 (http.server's name and contract)
        """As http.server's, plus single byte ranges for regular files."""
        path = self.translate_path(self.path)
        if os.path.isdir(path) or not os.path.isfile(path):
            return super().send_head()
        try:
            fh = open(path, "rb")  # noqa: SIM115 (the caller copies and closes it)
        except OSError:
            self.send_error(HTTPStatus.NOT_FOUND, "File not found")
            return None
        try:
            info = os.fstat(fh.fileno())
            size = info.st_size
            span = _byte_range(self.headers.get("Range"), size)
            if span == "unsatisfiable":
                fh.close()
                self.send_response(HTTPStatus.REQUESTED_RANGE_NOT_SATISFIABLE)
                self.send_header("Content-Range", f"bytes */{size}")
                self.send_header("Accept-Ranges", "bytes")
                self.send_header("Content-Length", "0")
                self.end_headers()
                return None
            start, stop = span if span else (0, size)
            self.send_response(HTTPStatus.PARTIAL_CONTENT if span else HTTPStatus.OK)
            self.send_header("Content-Type", self.guess_type(path))
            self.send_header("Content-Length", str(stop - start))
            if span:
                self.send_header("Content-Range", f"bytes {start}-{stop - 1}/{size}")
            self.send_header("Accept-Ranges", "bytes")
            self.send_header("Last-Modified", self.date_time_string(int(info.st_mtime)))
            self.end_headers()
            fh.seek(start)
            return _Limited(fh, stop - start)
        except Exception:
            fh.close()
            raise

    def do_GET(self) -> None:  # noqa: N802 (http.server's name)
        if self.path.startswith("/__sitegen__/version"):
            self._send(HTTPStatus.OK, str(self.state.version).encode(), "text/plain")
            return
        path = self.translate_path(self.path)
        if os.path.isdir(path):
            if not self.path.split("?", 1)[0].endswith("/"):
                super().do_GET()  # the redirect to the folder's URL with a slash
                return
            path = os.path.join(path, "index.html")
        if not os.path.exists(path):
            missing = os.path.join(self.directory, "404.html")
            if os.path.isfile(missing):
                self._send_html(HTTPStatus.NOT_FOUND, missing)
                return
        if path.endswith(".html") and os.path.isfile(path):
            self._send_html(HTTPStatus.OK, path)
            return
        super().do_GET()

    def _send_html(self, status: HTTPStatus, path: str) -> None:
        with open(path, "rb") as fh:
            data = fh.read()
        at = data.rfind(b"</body>")
        data = data[:at] + RELOAD_JS + data[at:] if at >= 0 else data + RELOAD_JS
        self._send(status, data, "text/html; charset=utf-8")

    def _send(self, status: HTTPStatus, body: bytes, content_type: str) -> None:
        self.send_response(status)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        self.wfile.write(body)


def _byte_range(header: str | None, size: int) -> tuple[int, int] | str | None:
    """The ``[start, stop)`` of a single-range ``Range`` header; None to send the whole file
    (no header, several ranges, a unit or form not understood, which HTTP lets a server
    ignore); "unsatisfiable" when the range starts past the end (or asks for no bytes)."""
    m = RANGE.match(header.strip()) if header else None
    if not m or m.group(1) == m.group(2) == "":
        return None
    first, last = m.group(1), m.group(2)
    if first == "":  # the last N bytes
        n = int(last)
        return (max(0, size - n), size) if n > 0 and size > 0 else "unsatisfiable"
    start = int(first)
    stop = size if last == "" else min(int(last) + 1, size)
    if last != "" and int(last) < start:
        return None  # not a valid range: ignored
    return (start, stop) if start < size else "unsatisfiable"


class _Limited(io.RawIOBase):
    """A file read from where it is for at most ``left`` bytes (a range's body)."""

    def __init__(self, fh, left: int):
        self.fh, self.left = fh, left

    def readable(self) -> bool:
        return True

    def read(self, n: int = -1) -> bytes:
        n = self.left if n is None or n < 0 else min(n, self.left)
        data = self.fh.read(n) if n > 0 else b""
        self.left -= len(data)
        return data

    def close(self) -> None:
        self.fh.close()
        super().close()


def _say(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def rebuild(opts: BuildOptions, state: _State, verbosity: int = 0) -> bool:
    """One build; print its problems, and which earlier problems are now fixed."""
    try:
        report = build(opts)
    except BuildError as exc:
        now = {str(d) for d in exc.diagnostics}
        for line in sorted(now - state.problems) if state.failed else sorted(now):
            _say(line)
        _say(f"sitegen: {exc}")
        _fixed(state, now)
        state.failed, state.problems = True, now
        return False
    now = {str(d) for d in report.diagnostics}
    for line in sorted(now - state.problems):
        _say(line)
    _fixed(state, now)
    if state.failed:
        _say("sitegen: fixed: the build succeeds again")
    state.failed, state.problems = False, now
    if not report.up_to_date:
        if verbosity >= 0:
            _say(f"sitegen: rebuilt {report.pages_rendered} page(s) in {report.seconds:.2f}s")
        if verbosity > 0:
            for rel in report.changed:
                _say(f"  changed {rel}")
        with state.lock:
            state.version += 1
    return True


def _fixed(state: _State, now: set[str]) -> None:
    for line in sorted(state.problems - now):
        _say(f"sitegen: fixed: {line}")


def serve(args: argparse.Namespace) -> int:
    verbosity = getattr(args, "verbosity", 0)
    try:
        if getattr(args, "dev_addr", None):
            host, port = parse_dev_addr(args.dev_addr)
        else:
            host, port = "127.0.0.1", check_port(args.port)
    except AddressError as exc:
        _say(f"sitegen serve: error: {exc}")
        return 2
    log = (lambda line: None) if verbosity < 0 else (lambda line: _say(line))
    opts = BuildOptions(
        source=args.source, output=args.output, strict=args.strict, clean=args.clean, log=log
    )
    try:
        _config, _content, output, cache_dir = resolve_paths(opts)
    except BuildError as exc:
        for d in exc.diagnostics:
            _say(str(d))
        _say(f"sitegen: {exc}")
        return 1
    state = _State()
    try:
        server = make_server(host, port, output, state)
    except AddressError as exc:
        _say(f"sitegen serve: error: {exc}")
        return 1
    try:
        return _run(server, opts, output, cache_dir, state, verbosity)
    finally:
        server.server_close()


def _run(server, opts: BuildOptions, output: Path, cache_dir: Path, state, verbosity: int) -> int:
    quick = "render_clips" in {f.name for f in dataclasses.fields(BuildOptions)}
    first = dataclasses.replace(opts, render_clips=False) if quick else opts
    rebuild(first, state, verbosity)
    opts.clean = False
    if not output.is_dir():
        _say("sitegen: nothing to serve: the first build failed")
        return 1
    host, port = server.server_address[:2]
    shown = f"[{host}]" if ":" in host else host
    _say(f"sitegen: serving {output} at http://{shown}:{port}/ (Ctrl+C to stop)")
    threading.Thread(target=server.serve_forever, daemon=True).start()
    skip = {output.resolve(), cache_dir.resolve()}
    source = opts.source.resolve()
    last = snapshot(source, skip)
    if quick:  # now the clips: the open page reloads when they are in
        rebuild(opts, state, verbosity)
    try:
        while True:
            time.sleep(0.5)
            now = snapshot(source, skip)
            if now != last:
                last = now
                rebuild(opts, state, verbosity)
    except KeyboardInterrupt:
        _say("sitegen: stopped")
    finally:
        server.shutdown()
    return 0
