"""``from coppeliasim_zmqremoteapi_client.asyncio import RemoteAPIClient``: the asyncio form of
CoppeliaSim's ZeroMQ client (``async with RemoteAPIClient() as client``, ``await
client.require('sim')``, every call awaited), served in process by the sitegen emulation.
"""

from sims.remote_api.zmq.async_client import RemoteAPIClient

__all__ = ["RemoteAPIClient"]
