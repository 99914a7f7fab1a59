"""``from coppeliasim_zmqremoteapi_client import RemoteAPIClient``: CoppeliaSim's ZeroMQ remote
API client (PyPI ``coppeliasim-zmqremoteapi-client``), served in process by the sitegen
emulation. This directory is put first on ``sys.path`` by ``sitegen remote-api run``, so this
module is found before an installed client. Nothing here opens a socket.
"""

from sims.remote_api.zmq.client import RemoteAPIClient

__all__ = ["RemoteAPIClient"]
