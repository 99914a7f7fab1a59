"""The connection a script in another Python keeps with the sitegen server (sims/remote_api/
rpc.py): one JSON object per line over TCP on 127.0.0.1, the port in SITEGEN_REMOTE_API_BRIDGE.

Standard library only, and Python 3.8 compatible: this file runs in the script's own
interpreter, not in sitegen's.
"""

import base64
import json
import os
import socket
import threading

_lock = threading.Lock()
_sock = None
_reader = None
_hello = None


def _encode(value):
    if isinstance(value, (bytes, bytearray)):
        tag = "$ba" if isinstance(value, bytearray) else "$b"
        return {tag: base64.b64encode(bytes(value)).decode("ascii")}
    if isinstance(value, tuple):
        return {"$t": [_encode(v) for v in value]}
    if isinstance(value, list):
        return [_encode(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _encode(v) for k, v in value.items()}
    if hasattr(value, "tolist") and getattr(value, "ndim", 0) >= 1 and value.size == 1:
        return {"$a": _encode(value.tolist())}  # a one-value array: ctypes takes it as a number
    if hasattr(value, "tolist") and not isinstance(value, str):
        return _encode(value.tolist())
    if hasattr(value, "item") and not isinstance(value, str):
        return value.item()  # numpy scalars
    return value


def _decode(value):
    if isinstance(value, list):
        return [_decode(v) for v in value]
    if isinstance(value, dict):
        if len(value) == 1:
            key, inner = next(iter(value.items()))
            if key == "$b":
                return base64.b64decode(inner)
            if key == "$ba":
                return bytearray(base64.b64decode(inner))
            if key == "$t":
                return tuple(_decode(v) for v in inner)
        return {k: _decode(v) for k, v in value.items()}
    return value


def _connect():
    global _sock, _reader
    if _sock is None:
        port = int(os.environ.get("SITEGEN_REMOTE_API_BRIDGE", "0") or 0)
        if not port:
            raise RuntimeError(
                "no sitegen server: run the script with `sitegen remote-api run "
                "SCRIPT --python PATH`"
            )
        _sock = socket.create_connection(("127.0.0.1", port))
        _sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        _reader = _sock.makefile("rb")
    return _sock


_EXCEPTIONS = {
    "KeyboardInterrupt": KeyboardInterrupt,
    "AttributeError": AttributeError,
    "TypeError": TypeError,
    "ValueError": ValueError,
    "IndexError": IndexError,
    "KeyError": KeyError,
}


def request(message):
    """Send one request and return its value (raising what the server raised)."""
    data = (json.dumps(_encode(message)) + "\n").encode("utf-8")
    with _lock:
        sock = _connect()
        sock.sendall(data)
        line = _reader.readline()
    if not line:
        raise ConnectionError("the sitegen server closed the connection")
    reply = json.loads(line)
    if "exc" in reply:
        kind, text = reply["exc"]
        if kind == "ArgumentError":
            import ctypes

            raise ctypes.ArgumentError(text)
        raise _EXCEPTIONS.get(kind, RuntimeError)(text)
    return _decode(reply.get("ret"))


def hello():
    global _hello
    if _hello is None:
        _hello = request({"op": "hello"})
    return _hello
