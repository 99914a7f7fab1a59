"""CoppeliaSim 4.3-4.5 name of the asyncio client."""

from coppeliasim_zmqremoteapi_client.asyncio import RemoteAPIClient  # noqa: F401

__all__ = ["RemoteAPIClient"]
