"""``from zmqRemoteApi import RemoteAPIClient``: the ZeroMQ client's module name in CoppeliaSim
4.3-4.5 (``client.getObject('sim')``, ``client.setStepping``, ``client.step``), served in process
by the sitegen emulation. Nothing here opens a socket.
"""

from sims.remote_api.zmq.client import RemoteAPIClient

__all__ = ["RemoteAPIClient"]
