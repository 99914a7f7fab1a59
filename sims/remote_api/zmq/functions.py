"""The one table of the ``sim.*`` functions the ZeroMQ emulation serves, and its servers.

The function modules are listed here (``MODULES``); each fills ``registry.FUNCTIONS`` through
its ``@api("name")`` decorators as it is imported, and nothing else imports them. A
:class:`~sims.remote_api.zmq.server.ZmqServer` is handed this table when it is made
(:func:`server_for`), so the server module never imports the functions that take it as their
first argument: the imports run one way (functions -> modules -> server).
"""

from __future__ import annotations

from ..client import Session
from . import objects, simulation
from .registry import FUNCTIONS, NOT_EMULATED, Fn
from .server import ZmqServer

MODULES = (objects, simulation)

__all__ = ["FUNCTIONS", "MODULES", "NOT_EMULATED", "load", "server_for"]


def load() -> dict[str, Fn]:
    """Every emulated function by its ``sim.*`` name."""
    return FUNCTIONS


def server_for(session: Session) -> ZmqServer:
    """The session's ZeroMQ server (created on first use)."""
    server = getattr(session, "zmq_server", None)
    if server is None:
        server = ZmqServer(session, FUNCTIONS)
        session.zmq_server = server  # type: ignore[attr-defined]
    return server
