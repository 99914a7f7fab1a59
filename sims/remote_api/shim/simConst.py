"""``import simConst``: the constants of the legacy remote API."""

from sims.remote_api.constants import *  # noqa: F403
from sims.remote_api.constants import __all__  # noqa: F401
