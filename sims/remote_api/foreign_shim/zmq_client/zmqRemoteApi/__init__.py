"""CoppeliaSim 4.3-4.5 name of the client (see coppeliasim_zmqremoteapi_client)."""

from coppeliasim_zmqremoteapi_client import RemoteAPIClient  # noqa: F401

__all__ = ["RemoteAPIClient"]
