"""``sitegen serve``: build, serve on 127.0.0.1, rebuild on change, reload the open page.

The server only ever binds to loopback. Watching is done by polling file stats twice a
second (cheap for a course site, and needs no extra dependency); the build itself still
decides what changed by content hash. Served HTML gets a tiny script that polls
``/__sitegen__/version`` and reloads the page when a rebuild lands; the files on disk are
never modified, so the built site stays byte-identical to a plain ``sitegen build``.
"""

from __future__ import annotations

import argparse
import functools
import os
import sys
import threading
import time
from http import HTTPStatus
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

from sitegen.build import BuildOptions, build, resolve_paths
from sitegen.errors import BuildError

RELOAD_JS = b"""<script>(function(){var v=null;function poll(){fetch("/__sitegen__/version",{cache:"no-store"})
.then(function(r){return r.text()}).then(function(t){if(v!==null&&t!==v){location.reload()}v=t})
.catch(function(){}).finally(function(){setTimeout(poll,1000)})}poll()})();</script>"""


class _State:
    def __init__(self) -> None:
        self.version = 0
        self.lock = threading.Lock()


class _Handler(SimpleHTTPRequestHandler):
    state: _State

    def log_message(self, format: str, *args) -> None:  # noqa: A002 (http.server's name)
        pass

    def do_GET(self) -> None:  # noqa: N802 (http.server's name)
        if self.path.startswith("/__sitegen__/version"):
            self._send(str(self.state.version).encode(), "text/plain")
            return
        path = self.translate_path(self.path)
        if os.path.isdir(path):
            path = os.path.join(path, "index.html")
        if path.endswith(".html") and os.path.isfile(path):
            with open(path, "rb") as fh:
                data = fh.read()
            at = data.rfind(b"</body>")
            data = data[:at] + RELOAD_JS + data[at:] if at >= 0 else data + RELOAD_JS
            self._send(data, "text/html; charset=utf-8")
            return
        super().do_GET()

    def _send(self, body: bytes, content_type: str) -> None:
        self.send_response(HTTPStatus.OK)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.end_headers()
        self.wfile.write(body)


def _snapshot(root: Path, skip: set[Path]) -> tuple:
    entries = []
    for dirpath, dirnames, files in os.walk(root):
        here = Path(dirpath)
        dirnames[:] = sorted(
            d for d in dirnames if not d.startswith(".") and (here / d).resolve() not in skip
        )
        for name in sorted(files):
            try:
                st = (here / name).stat()
            except OSError:
                continue
            entries.append((dirpath, name, st.st_size, st.st_mtime_ns))
    return tuple(entries)


def _rebuild(opts: BuildOptions, state: _State) -> None:
    try:
        report = build(opts)
    except BuildError as exc:
        for d in exc.diagnostics:
            print(d, file=sys.stderr)
        print(f"sitegen: {exc}", file=sys.stderr)
        return
    for d in report.diagnostics:
        print(d, file=sys.stderr)
    if not report.up_to_date:
        print(
            f"sitegen: rebuilt {report.pages_rendered} page(s) in {report.seconds:.2f}s",
            file=sys.stderr,
        )
        with state.lock:
            state.version += 1


def serve(args: argparse.Namespace) -> int:
    opts = BuildOptions(
        source=args.source, output=args.output, strict=args.strict, clean=args.clean
    )
    _config, _content, output, cache_dir = resolve_paths(opts)
    opts.clean = False
    state = _State()
    _rebuild(
        BuildOptions(source=args.source, output=args.output, strict=args.strict, clean=args.clean),
        state,
    )
    if not output.is_dir():
        print("sitegen: nothing to serve: the first build failed", file=sys.stderr)
        return 1
    handler = functools.partial(_Handler, directory=str(output))
    _Handler.state = state
    server = ThreadingHTTPServer(("127.0.0.1", args.port), handler)
    host, port = server.server_address[:2]
    print(f"sitegen: serving {output} at http://{host}:{port}/ (Ctrl+C to stop)", file=sys.stderr)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    skip = {output.resolve(), cache_dir.resolve()}
    source = args.source.resolve()
    last = _snapshot(source, skip)
    try:
        while True:
            time.sleep(0.5)
            now = _snapshot(source, skip)
            if now != last:
                last = now
                _rebuild(opts, state)
    except KeyboardInterrupt:
        print("sitegen: stopped", file=sys.stderr)
    finally:
        server.shutdown()
        server.server_close()
    return 0
