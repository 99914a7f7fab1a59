"""``sitegen serve``: byte ranges (issue 26: Safari plays a video only from a 206), a NUL in the
path, 100 clients at once and silent ones (issue 33; docs/security.md)."""

from __future__ import annotations

import http.client
import socket
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from sitegen import serve

VIDEO = bytes(range(256)) * 40  # 10,240 bytes


@pytest.fixture()
def server(tmp_path: Path):
    site = tmp_path / "site"
    (site / "clips" / "a").mkdir(parents=True)
    (site / "clips" / "a" / "clip.webm").write_bytes(VIDEO)
    (site / "index.html").write_text("<html><body>home</body></html>", encoding="utf-8")
    (site / "404.html").write_text("<html><body>missing</body></html>", encoding="utf-8")
    srv = serve.make_server("127.0.0.1", 0, site, serve._State())
    thread = threading.Thread(target=srv.serve_forever, daemon=True)
    thread.start()
    try:
        yield srv
    finally:
        srv.shutdown()
        srv.server_close()


def _get(srv, path: str, method: str = "GET", **headers: str):
    conn = http.client.HTTPConnection("127.0.0.1", srv.server_address[1], timeout=20)
    try:
        conn.request(method, path, headers=headers)
        r = conn.getresponse()
        return r.status, dict(r.getheaders()), r.read()
    finally:
        conn.close()


def test_a_single_byte_range_is_answered_with_206(server):
    url = "/clips/a/clip.webm"
    status, head, body = _get(server, url)
    assert status == 200 and body == VIDEO and head["Accept-Ranges"] == "bytes"
    assert head["Content-Type"] == "video/webm"
    for asked, (start, stop) in {
        "bytes=0-1": (0, 2),  # what Safari asks first
        "bytes=100-199": (100, 200),
        "bytes=10000-": (10000, len(VIDEO)),
        "bytes=-40": (len(VIDEO) - 40, len(VIDEO)),
        "bytes=10200-99999": (10200, len(VIDEO)),  # past the end: up to the end
    }.items():
        status, head, body = _get(server, url, Range=asked)
        assert status == 206, asked
        assert body == VIDEO[start:stop] and head["Content-Length"] == str(stop - start)
        assert head["Content-Range"] == f"bytes {start}-{stop - 1}/{len(VIDEO)}"
        assert head["Accept-Ranges"] == "bytes"
    status, head, body = _get(server, url, "HEAD", Range="bytes=5-9")
    assert status == 206 and body == b"" and head["Content-Range"] == f"bytes 5-9/{len(VIDEO)}"


def test_an_unsatisfiable_range_is_416_and_others_are_ignored(server):
    url = "/clips/a/clip.webm"
    for asked in ("bytes=10240-", "bytes=99999-100000", "bytes=-0"):
        status, head, body = _get(server, url, Range=asked)
        assert (status, body) == (416, b""), asked
        assert head["Content-Range"] == f"bytes */{len(VIDEO)}"
    # several ranges, other units, nonsense: the whole file, as HTTP allows
    for asked in ("bytes=0-1,5-6", "items=0-1", "bytes=5-2", "bytes=x-y", "bytes=-"):
        status, head, body = _get(server, url, Range=asked)
        assert (status, body) == (200, VIDEO), asked
    status, _head, body = _get(server, "/missing.webm", Range="bytes=0-1")
    assert status == 404 and b"missing" in body


def test_a_nul_in_the_path_is_a_404_not_a_traceback(server, capfd):
    for path in ("/.%00./etc/passwd", "/%00", "/clips/%00/clip.webm", "/index.html%00.png"):
        status, _head, body = _get(server, path)
        assert status == 404 and b"missing" in body, path
    assert "Traceback" not in capfd.readouterr().err


def test_a_hundred_clients_at_once_are_all_answered(server):
    """Before the server accepts anything, 100 connections complete their handshake (the
    listen queue was 5: the rest waited for retransmitted SYNs, some past their timeout)."""
    assert server.socket.getsockopt(socket.SOL_SOCKET, socket.SO_ACCEPTCONN) == 1
    assert serve.BACKLOG >= 100

    def fetch(i: int) -> int:
        total = 0
        for _ in range(5):
            status, _head, body = _get(server, "/clips/a/clip.webm", Range=f"bytes={i}-{i}")
            assert status == 206 and body == VIDEO[i : i + 1]
            total += 1
        return total

    started = time.monotonic()
    with ThreadPoolExecutor(100) as pool:
        assert sum(pool.map(fetch, range(100))) == 500
    assert time.monotonic() - started < 60


def test_the_listen_queue_holds_a_hundred_connections(tmp_path):
    srv = serve.make_server("127.0.0.1", 0, tmp_path, serve._State())  # not accepting yet
    clients = []
    try:
        for _ in range(100):
            c = socket.socket()
            c.setblocking(False)
            c.connect_ex(srv.server_address)
            clients.append(c)
        time.sleep(0.5)
        done = 0
        for c in clients:  # a completed handshake: the socket is writable, with no error
            if c.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR) == 0:
                try:
                    c.getpeername()
                    done += 1
                except OSError:
                    pass
        assert done == 100
    finally:
        for c in clients:
            c.close()
        srv.server_close()


def test_a_silent_client_is_dropped_after_the_request_timeout(server, monkeypatch):
    assert serve._Handler.timeout == serve.REQUEST_TIMEOUT <= 60  # none before: held forever
    monkeypatch.setattr(serve._Handler, "timeout", 1.0)
    slow = socket.create_connection(server.server_address, timeout=10)
    try:
        slow.sendall(b"GET /index.html HTTP/1.1\r\nHost: x\r\n")  # and never the blank line
        started = time.monotonic()
        assert _get(server, "/index.html")[0] == 200  # others are served meanwhile
        assert slow.recv(100) == b""  # closed by the server
        assert 0.5 < time.monotonic() - started < 8
    finally:
        slow.close()
