"""``import sim``: CoppeliaSim's legacy remote API, emulated on sitegen's pybullet scenes.

This directory is put first on ``sys.path`` by ``sitegen remote-api run`` so that course
scripts run unchanged. Nothing here opens a socket.
"""

from sims.remote_api.api import *  # noqa: F403
from sims.remote_api.api import __all__, __getattr__  # noqa: F401
